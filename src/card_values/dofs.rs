//! Grid-point component sets (`C`, `PS`, `CM` fields): which of T1 T2 T3 R1 R2 R3 a
//! constraint, rigid element or load acts on.

/// A set of grid-point components (1–6 = T1 T2 T3 R1 R2 R3) as written in `C`, `PS`, `CM` fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize)]
pub struct Dofs(pub u8);

impl Dofs {
    /// No component.
    pub const NONE: Dofs = Dofs(0);
    /// All six components.
    pub const ALL: Dofs = Dofs(0b11_1111);

    /// Parse a component code such as `123456` or `35`; `None` for a digit outside 1–6 or a
    /// repeated digit.
    pub fn parse(code: i64) -> Option<Dofs> {
        if code < 0 {
            return None;
        }
        if code == 0 {
            return Some(Dofs::NONE);
        }
        let mut bits = 0u8;
        for c in code.to_string().chars() {
            let d = c.to_digit(10)?;
            if !(1..=6).contains(&d) || bits & (1 << (d - 1)) != 0 {
                return None;
            }
            bits |= 1 << (d - 1);
        }
        Some(Dofs(bits))
    }

    /// True when component `c` (1–6) is in the set.
    pub fn contains(self, c: usize) -> bool {
        (1..=6).contains(&c) && self.0 & (1 << (c - 1)) != 0
    }

    /// The components in increasing order (1-based).
    pub fn components(self) -> impl Iterator<Item = usize> {
        (1..=6).filter(move |&c| self.contains(c))
    }

    /// True for the empty set.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
}

impl std::fmt::Display for Dofs {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for c in self.components() {
            write!(f, "{c}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dofs_parse() {
        assert_eq!(Dofs::parse(123456), Some(Dofs::ALL));
        assert_eq!(Dofs::parse(35).unwrap().to_string(), "35");
        assert_eq!(Dofs::parse(17), None);
        assert_eq!(Dofs::parse(11), None);
    }
}
