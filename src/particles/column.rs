//! The optional per-particle columns of stateful features (the history memory, a field's cell
//! hints): each is a [`Column`], registered once in [`super::Particles`], whose `push` and
//! `retain` carry it with the particles — no feature sizes or renumbers its column by hand.
//!
//! Its values are shared, not owned (`Arc`): the flight kernel holds a share of the columns it
//! reads for a whole step ([`Column::share`]) while stage 1 writes the rest of the store, and
//! once the kernel is gone the column is the values' one owner again, so writing it copies
//! nothing (a column still shared when written is copied first: never wrong, only slower).

use std::sync::Arc;

/// An optional per-particle column: `width` values per particle (the history's modes, one cell
/// hint), none at all while its feature is off (width 0), a new particle's values `fresh`.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Column<T> {
    values: Arc<Vec<T>>,
    width: usize,
    fresh: T,
}

impl<T: Copy> Column<T> {
    /// A column of `width` values for each of `n` particles, all `fresh`.
    pub fn new(width: usize, fresh: T, n: usize) -> Self {
        Column { values: Arc::new(vec![fresh; width * n]), width, fresh }
    }

    /// The column of a feature that is off: no values, and none pushed.
    pub fn off(fresh: T) -> Self {
        Column { values: Arc::default(), width: 0, fresh }
    }

    /// The same, with its values reserved for `n` particles first: a machine that cannot give
    /// them is an error rather than an abort.
    pub fn try_new(width: usize, fresh: T, n: usize) -> Result<Self, std::collections::TryReserveError> {
        let mut values = Vec::new();
        values.try_reserve_exact(width * n)?;
        values.resize(width * n, fresh);
        Ok(Column { values: Arc::new(values), width, fresh })
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
        Arc::make_mut(&mut self.values).as_mut_slice()
    }

    /// A share of the values, read-only, for as long as a step's kernel reads them while the
    /// rest of the store is written (the column keeps them too).
    pub fn share(&self) -> Arc<Vec<T>> {
        Arc::clone(&self.values)
    }

    /// A new particle's values, `fresh`.
    pub fn push(&mut self) {
        if self.width > 0 {
            let values = Arc::make_mut(&mut self.values);
            values.resize(values.len() + self.width, self.fresh);
        }
    }

    /// Keeps the values of the particles with `keep[i]`, in their order.
    pub fn retain(&mut self, keep: &[bool]) {
        if self.width == 0 {
            return;
        }
        let width = self.width;
        let mut k = 0;
        Arc::make_mut(&mut self.values).retain(|_| {
            let kept = keep[k / width];
            k += 1;
            kept
        });
    }

    /// The column of the particles `rows` (indices into this one, in the order given): what a
    /// rank sends of its particles (`crate::ranks`).
    pub fn select(&self, rows: &[usize]) -> Self {
        let w = self.width;
        let mut values = Vec::with_capacity(w * rows.len());
        for &i in rows {
            values.extend_from_slice(&self.values[i * w..(i + 1) * w]);
        }
        Column { values: Arc::new(values), width: w, fresh: self.fresh }
    }

    /// Appends `other`'s particles (a column of the same feature, or one that is off when this
    /// one is off).
    pub fn append(&mut self, other: &Self) {
        if self.width > 0 {
            Arc::make_mut(&mut self.values).extend_from_slice(&other.values);
        }
    }

    /// Exchanges the values with `other` (the step's end-of-step copy), the width kept.
    pub fn swap_values(&mut self, other: &mut Vec<T>) {
        std::mem::swap(Arc::make_mut(&mut self.values), other);
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

    #[test]
    fn a_share_keeps_the_values_of_the_step_while_the_column_is_written() {
        let mut c = Column::new(1, 0u32, 2);
        let share = c.share();
        c.values_mut()[0] = 7;
        assert_eq!((&share[..], c.values()), (&[0, 0][..], &[7, 0][..]));
        drop(share);
        let mut end = vec![5, 6];
        c.swap_values(&mut end);
        assert_eq!((c.values(), &end[..]), (&[5, 6][..], &[7, 0][..]));
    }
}
