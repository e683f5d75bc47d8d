//! The pair at the heart of differential rendering (Knecht §2.7, TVCG Eq. 1–2).
//!
//! `rv` is radiance with real *and* virtual content (`L_rv`), `r` with real content only
//! (`L_r`). Both halves must come from the same light paths, so every producer builds them
//! together and every consumer takes them together: this type makes that the only way.

/// A value computed twice from the same paths: with virtual content (`rv`) and without (`r`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Differential<T> {
    /// `L_rv`: the scene with real and virtual objects and lights.
    pub rv: T,
    /// `L_r`: the scene with real objects and real lights only.
    pub r: T,
}

impl<T> Differential<T> {
    /// Applies `f` to both halves.
    pub fn map<U>(self, mut f: impl FnMut(T) -> U) -> Differential<U> {
        Differential { rv: f(self.rv), r: f(self.r) }
    }

    /// Borrows both halves.
    pub fn as_ref(&self) -> Differential<&T> {
        Differential { rv: &self.rv, r: &self.r }
    }
}

/// Accumulates both halves at once (sums over paths keep the pair together).
impl<T: std::ops::AddAssign> std::ops::AddAssign for Differential<T> {
    fn add_assign(&mut self, other: Self) {
        self.rv += other.rv;
        self.r += other.r;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adding_adds_each_half_to_its_own() {
        let mut d = Differential { rv: 1.0, r: 2.0 };
        d += Differential { rv: 10.0, r: 20.0 };
        assert_eq!(d, Differential { rv: 11.0, r: 22.0 });
    }
}
