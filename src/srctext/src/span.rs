//! Where a piece of a source text is: the byte range every reader's syntax tree carries, so that an error
//! about it can be [`crate::locate`]d.

/// A byte range in one source text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Span {
    pub start: usize,
    pub end: usize,
}

impl Span {
    pub fn new(start: usize, end: usize) -> Self {
        Span { start, end }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span::new(self.start.min(other.start), self.end.max(other.end))
    }
}

#[cfg(test)]
mod tests {
    use super::Span;

    #[test]
    fn to_covers_both_in_either_order() {
        let (a, b) = (Span::new(3, 5), Span::new(8, 12));
        assert_eq!(a.to(b), Span::new(3, 12));
        assert_eq!(b.to(a), Span::new(3, 12));
        assert_eq!(Span::new(2, 20).to(a), Span::new(2, 20));
    }
}
