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
