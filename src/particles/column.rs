//! The optional per-particle columns of stateful features (the history memory, a field's cell
//! hints): each is a [`Column`], registered once in [`super::Particles`], whose `push` and
//! `retain` carry it with the particles — no feature sizes or renumbers its column by hand.

/// An optional per-particle column: `width` values per particle (the history's modes, one cell
/// hint), none at all while its feature is off (width 0), a new particle's values `fresh`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Column<T> {
    values: Vec<T>,
    width: usize,
    fresh: T,
}

impl<T: Copy> Column<T> {
    /// A column of `width` values for each of `n` particles, all `fresh`.
    pub fn new(width: usize, fresh: T, n: usize) -> Self {
        Column { values: vec![fresh; width * n], width, fresh }
    }

    /// The column of a feature that is off: no values, and none pushed.
    pub fn off(fresh: T) -> Self {
        Column { values: Vec::new(), width: 0, fresh }
    }

    /// The same, with its values reserved for `n` particles first: a machine that cannot give
    /// them is an error rather than an abort.
    pub fn try_new(width: usize, fresh: T, n: usize) -> Result<Self, std::collections::TryReserveError> {
        let mut values = Vec::new();
        values.try_reserve_exact(width * n)?;
        values.resize(width * n, fresh);
        Ok(Column { values, width, fresh })
    }

    /// Values per particle; 0 while its feature is off.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Whether its feature is on.
    pub fn is_on(&self) -> bool {
        self.width > 0
    }

    /// The values, `width` per particle in particle order.
    pub fn values(&self) -> &[T] {
        &self.values
    }

    /// The values, to write.
    pub fn values_mut(&mut self) -> &mut [T] {
        &mut self.values
    }

    /// A new particle's values, `fresh`.
    pub fn push(&mut self) {
        self.values.resize(self.values.len() + self.width, self.fresh);
    }

    /// Keeps the values of the particles with `keep[i]`, in their order.
    pub fn retain(&mut self, keep: &[bool]) {
        if self.width == 0 {
            return;
        }
        let width = self.width;
        let mut k = 0;
        self.values.retain(|_| {
            let kept = keep[k / width];
            k += 1;
            kept
        });
    }

    /// Exchanges the values with `other` (the step's end-of-step copy, or a column taken out
    /// for the step), the width kept.
    pub fn swap_values(&mut self, other: &mut Vec<T>) {
        std::mem::swap(&mut self.values, other);
    }

    /// Takes the values out for the step (the flight kernel reads them while the stages write
    /// the particles), leaving none; [`Column::swap_values`] puts values back.
    pub fn take_values(&mut self) -> Vec<T> {
        std::mem::take(&mut self.values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_column_grows_and_shrinks_with_the_particles_by_its_width() {
        let mut c = Column::new(2, 0u32, 3);
        c.values_mut().copy_from_slice(&[1, 1, 2, 2, 3, 3]);
        c.push();
        assert_eq!(c.values(), &[1, 1, 2, 2, 3, 3, 0, 0]);
        c.retain(&[true, false, true, true]);
        assert_eq!(c.values(), &[1, 1, 3, 3, 0, 0]);
        let mut off = Column::off(0u32);
        off.push();
        off.retain(&[true]);
        assert!(off.values().is_empty() && !off.is_on());
    }
}
