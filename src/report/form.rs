//! The live page's goal form and cancel buttons (`--http-goals`): a goal is sent as a MAVLink upload to the
//! companion's own ground-station endpoint (the same intake, acceptance test and insertion as any ground
//! station's upload, the same verdict texts back); a held goal is withdrawn by uploading its station's list
//! without it. Both POSTs pass the page's Host and Origin check first.

use std::collections::BTreeMap;
use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;

use axum::extract::{Form, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Json, Response};

use super::live::AppState;
use crate::vehicle::goal_client::{GoalSendError, GoalSendReport};
use crate::vehicle::goals::is_final_verdict_text;
use crate::vehicle::items::MissionItem;

/// Sends a goal upload through the companion's intake and returns the ground station's account.
pub type GoalSubmit = Arc<
    dyn Fn(
            Vec<MissionItem>,
        ) -> Pin<Box<dyn Future<Output = Result<GoalSendReport, GoalSendError>> + Send>>
        + Send
        + Sync,
>;

/// Turns the form's picture goal (east, north metres from home) into the items of an upload.
pub type GoalItems = Arc<dyn Fn(&PictureGoal) -> Vec<MissionItem> + Send + Sync>;

/// The goal form's fields.
#[derive(Clone, Debug, PartialEq)]
pub struct PictureGoal {
    pub east: f64,
    pub north: f64,
    /// End of the start window, seconds after the mission's origin.
    pub window_end_s: f64,
    pub d_achiev_s: f64,
}

/// Withdraws a goal a ground station holds, by the mission protocol (that station's list uploaded again
/// without it), and returns the ground station's account.
pub type GoalCancelFn = Arc<
    dyn Fn(String) -> Pin<Box<dyn Future<Output = Result<GoalSendReport, CancelError>> + Send>>
        + Send
        + Sync,
>;

/// Why a goal could not be withdrawn.
#[derive(Debug, thiserror::Error)]
pub enum CancelError {
    #[error(transparent)]
    NotHeld(#[from] crate::vehicle::held::WithdrawError),
    #[error("upload failed: {0}")]
    Send(#[from] GoalSendError),
}

/// What the goal form needs: how to build the upload and how to send it; how to withdraw a held goal.
#[derive(Clone)]
pub struct GoalForm {
    pub items: GoalItems,
    pub submit: GoalSubmit,
    pub cancel: Option<GoalCancelFn>,
}

/// The answer to a goal submitted with the form.
#[derive(Debug, serde::Serialize, serde::Deserialize, PartialEq)]
pub struct GoalAnswer {
    pub accepted: bool,
    /// The intake's verdict (`g8 accepted: …` / `g8 rejected: <reason>`), or why nothing was sent.
    pub verdict: String,
}

fn answer(code: StatusCode, accepted: bool, verdict: String) -> Response {
    (code, Json(GoalAnswer { accepted, verdict })).into_response()
}

/// The form, when this POST may use it: the page's own (Host and Origin) and the form on.
fn form_for<'a>(
    s: &'a AppState,
    headers: &axum::http::HeaderMap,
) -> Result<&'a GoalForm, (StatusCode, String)> {
    let header = |name: axum::http::HeaderName| headers.get(name).and_then(|v| v.to_str().ok());
    let from = super::origin::check(
        header(axum::http::header::HOST),
        header(axum::http::header::ORIGIN),
        s.bound,
    );
    if let Err(e) = from {
        return Err((StatusCode::FORBIDDEN, e.to_string()));
    }
    s.form.as_ref().ok_or_else(|| {
        (
            StatusCode::FORBIDDEN,
            "the goal form is disabled (start with --http-goals)".into(),
        )
    })
}

/// Answers a POST with `then` on the form once [`form_for`] lets it through, else with why not.
async fn posted<'a, Fut: Future<Output = Response>>(
    s: &'a AppState,
    headers: &axum::http::HeaderMap,
    then: impl FnOnce(&'a GoalForm) -> Fut,
) -> Response {
    match form_for(s, headers) {
        Ok(form) => then(form).await,
        Err((code, why)) => answer(code, false, why),
    }
}

/// Withdraws the held goal the form field `goal` names; `accepted` says it was cancelled.
pub(super) async fn cancel(
    State(s): State<Arc<AppState>>,
    headers: axum::http::HeaderMap,
    Form(fields): Form<BTreeMap<String, String>>,
) -> Response {
    posted(&s, &headers, |form| cancel_with(form, fields)).await
}

async fn cancel_with(form: &GoalForm, fields: BTreeMap<String, String>) -> Response {
    let Some(cancel) = &form.cancel else {
        return answer(
            StatusCode::FORBIDDEN,
            false,
            "this page cannot withdraw goals".into(),
        );
    };
    let Some(name) = fields.get("goal").map(|g| g.trim().to_string()) else {
        return answer(StatusCode::BAD_REQUEST, false, "missing field goal".into());
    };
    match cancel(name.clone()).await {
        Ok(report) => {
            let (done, verdict) = cancel_verdict(&name, &report);
            answer(StatusCode::OK, done, verdict)
        }
        Err(e @ CancelError::NotHeld(_)) => answer(StatusCode::CONFLICT, false, e.to_string()),
        Err(e) => answer(StatusCode::BAD_GATEWAY, false, e.to_string()),
    }
}

/// Cancelled when the companion said so for `name`; the verdict is its texts (or the upload's failure).
pub fn cancel_verdict(name: &str, r: &GoalSendReport) -> (bool, String) {
    let prefix = format!("{name} cancelled:");
    let done = r.failure.is_none() && r.texts.iter().any(|t| t.starts_with(&prefix));
    let mut text = r.texts.join("; ");
    if let Some(f) = &r.failure {
        text = format!("upload refused: {f}; {text}");
    }
    if text.is_empty() {
        text = format!("no answer about {name}");
    }
    (done, text)
}

/// Uploads the form's goal; `accepted` with the intake's verdict.
pub(super) async fn goal(
    State(s): State<Arc<AppState>>,
    headers: axum::http::HeaderMap,
    Form(fields): Form<BTreeMap<String, String>>,
) -> Response {
    posted(&s, &headers, |form| goal_with(form, fields)).await
}

async fn goal_with(form: &GoalForm, fields: BTreeMap<String, String>) -> Response {
    let goal = match parse_goal(&fields) {
        Ok(g) => g,
        Err(e) => return answer(StatusCode::BAD_REQUEST, false, e.to_string()),
    };
    let items = (form.items)(&goal);
    match (form.submit)(items).await {
        Ok(report) => {
            let (accepted, verdict) = verdict_of(&report);
            answer(StatusCode::OK, accepted, verdict)
        }
        Err(e) => answer(
            StatusCode::BAD_GATEWAY,
            false,
            format!("upload failed: {e}"),
        ),
    }
}

/// Why the page's goal form cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FormError {
    #[error("missing field {field}")]
    Missing { field: String },
    #[error("{field}: not a number: {value:?}")]
    NotANumber { field: String, value: String },
}

/// The form's fields as numbers; a missing or non-numeric field names itself.
pub fn parse_goal(fields: &BTreeMap<String, String>) -> Result<PictureGoal, FormError> {
    let num = |k: &str| -> Result<f64, FormError> {
        let v = fields.get(k).ok_or_else(|| FormError::Missing {
            field: k.to_string(),
        })?;
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| FormError::NotANumber {
                field: k.to_string(),
                value: v.clone(),
            })
    };
    Ok(PictureGoal {
        east: num("east")?,
        north: num("north")?,
        window_end_s: num("window_end_s")?,
        d_achiev_s: num("d_achiev_s")?,
    })
}

/// Accepted when the upload was and every final verdict text says so; the verdict is those texts (or the
/// upload's failure).
pub fn verdict_of(r: &GoalSendReport) -> (bool, String) {
    if let Some(f) = &r.failure {
        let texts = r.texts.join("; ");
        return (false, format!("upload refused: {f}; {texts}"));
    }
    let finals: Vec<&String> = r
        .texts
        .iter()
        .filter(|t| is_final_verdict_text(t))
        .collect();
    let accepted = !finals.is_empty() && finals.iter().all(|t| t.contains(" accepted:"));
    let shown = if finals.is_empty() {
        r.texts.iter().collect()
    } else {
        finals
    };
    let text: Vec<&str> = shown.iter().map(|s| s.as_str()).collect();
    (accepted, text.join("; "))
}
