"""Drives the live page in headless Chromium (see browser.sh). Every wait is bounded."""
import re
import sys
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

url = sys.argv[1]
opts = webdriver.ChromeOptions()
opts.binary_location = "/usr/bin/chromium"
for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1200,2000"):
    opts.add_argument(a)
driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)


def js(expr):
    """One atomic read of the page (the server replaces the body a few times a second)."""
    return driver.execute_script("try { return " + expr + "; } catch (e) { return null; }")


def wait(what, cond, seconds=60):
    try:
        return WebDriverWait(driver, seconds, poll_frequency=0.2).until(lambda d: cond())
    except Exception:
        print("FAILED waiting for: " + what, file=sys.stderr)
        print((js("document.getElementById('live').innerText") or "")[:3000], file=sys.stderr)
        raise


def now_ms():
    return int(js("document.getElementById('state').dataset.nowMs") or -1)


def attr_int(css, name):
    v = js("document.querySelector('" + css + "').getAttribute('" + name + "')")
    return int(v) if v is not None else -1


def count(css):
    return int(js("document.querySelectorAll('" + css + "').length") or 0)


try:
    driver.get(url)
    # Goals, actions and the resource plots appear...
    wait("the goals table", lambda: count("#goals tr[data-goal]") >= 5)
    wait("an executed action", lambda: attr_int("#gantt", "data-bars") >= 1)
    wait("the storage plot", lambda: count("div.resource[data-resource=STORAGE] svg") == 1)
    wait("the battery plot", lambda: count("div.resource[data-resource=BATTERY] svg") == 1)
    t0, bars0 = now_ms(), attr_int("#gantt", "data-bars")
    samples0 = attr_int("div.resource[data-resource=BATTERY]", "data-samples")
    print(f"page shows t={t0} ms, {bars0} actions, {samples0} battery levels")
    # ... and update as the mission runs (pushed by the server, no reload).
    wait("time to move on", lambda: now_ms() > t0 + 5000)
    wait("more actions", lambda: attr_int("#gantt", "data-bars") > bars0)
    wait("more battery levels", lambda: attr_int("div.resource[data-resource=BATTERY]", "data-samples") > samples0)
    print(f"page updated: t={now_ms()} ms, {attr_int('#gantt', 'data-bars')} actions")

    def submit(east, north, window_end_s):
        for name, value in (("east", east), ("north", north), ("window_end_s", window_end_s), ("d_achiev_s", 60)):
            field = driver.find_element(By.NAME, name)
            field.clear()
            field.send_keys(str(value))
        result = driver.find_element(By.ID, "goal-result")
        before = result.text
        driver.find_element(By.CSS_SELECTOR, "#goal-form button").click()
        wait("the verdict", lambda: re.search(r"(accepted|rejected)", result.text) and result.text != before, 90)
        return result.text, result.get_attribute("class")

    text, cls = submit(30, 2, 1800)
    print("valid goal: " + text)
    assert cls == "accepted" and " accepted: " in text, text
    name = text.split(" ")[0]
    wait(name + " in the goals table", lambda: count(f"#goals tr[data-goal={name}]") == 1)
    # Issue 30: the operator reads it as accepted (not "pending"), where it came from, and can withdraw it.
    row = f"#goals tr[data-goal={name}]"
    wait(name + " accepted", lambda: js(f"document.querySelector('{row}').dataset.state") == "accepted")
    # Where it came from: the page may render the executive's "accepted" one refresh before the link's
    # held list names the station (then it reads "upload" for that refresh).
    source = lambda: js(f"document.querySelector('{row}').children[5].textContent")
    wait(name + " from ground station 255/190", lambda: source() == "ground station 255/190", 10)
    wait("the vehicle's mode", lambda: js("document.getElementById('vehicle-mode').textContent") == "GUIDED")
    print("vehicle: mode " + js("document.getElementById('vehicle-mode').textContent")
          + ", armed " + js("document.getElementById('vehicle-armed').textContent")
          + ", battery " + js("document.getElementById('vehicle-battery').textContent")
          + ", link " + js("document.getElementById('vehicle-link').textContent"))
    result = driver.find_element(By.ID, "goal-result")
    # The body is replaced a few times a second: find the button and click it in one script.
    clicked = js(f"(function(){{const b=document.querySelector('{row} button[data-cancel]');"
                 "if(!b)return false;b.click();return true;})()")
    assert clicked, "no cancel button for " + name
    wait("the cancel's verdict", lambda: "cancelled" in result.text, 90)
    print("cancel: " + result.text)
    assert result.get_attribute("class") == "cancelled", result.text
    wait(name + " cancelled in the table",
         lambda: js(f"document.querySelector('{row}').dataset.state") == "cancelled")
    assert count(f"{row} button[data-cancel]") == 0

    text, cls = submit(30, 2, 1)
    print("goal whose start window is over: " + text)
    assert cls == "rejected" and " rejected: " in text and "start window" in text, text
    print("browser test passed")
finally:
    driver.quit()
