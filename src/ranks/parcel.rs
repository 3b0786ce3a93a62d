//! Particles sent from one rank to another — to their cluster's new owner, or to rank 0 for a
//! frame or a checkpoint — with their lasting contacts and their walls' last forces, and the
//! merge of such parts into one process's id order.

use crate::contact::{LastingContact, WallContact};
use crate::particles::Particles;
use crate::pipeline::World;

/// Particles sent to another rank (when they change owner, or to rank 0 for a checkpoint),
/// with their lasting contacts and their walls' last forces.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct Parcel {
    pub particles: Particles,
    /// The lasting contacts among them, by particle ids, in this rank's order.
    pub lasting: Vec<([u32; 2], LastingContact)>,
    pub walls: Vec<WallContact>,
}

impl Parcel {
    /// All of `world`'s particles, lasting contacts and walls' forces.
    pub fn of(world: &World) -> Parcel {
        Parcel {
            particles: world.particles.clone(),
            lasting: world.lasting.iter().map(|c| by_id(&world.particles, c)).collect(),
            walls: world.wall_contacts.clone(),
        }
    }

    /// What goes to rank `r`: `world`'s particles at `rows` (those with `owner[i] == r`, in
    /// index order), the lasting contacts among them (both particles of one have one owner: they
    /// are one cluster) and their walls' last forces.
    pub fn to_rank(world: &World, owner: &[usize], r: usize, rows: &[usize]) -> Parcel {
        let p = &world.particles;
        Parcel {
            particles: p.select(rows),
            lasting: world.lasting.iter().filter(|c| owner[c.a as usize] == r).map(|c| by_id(p, c)).collect(),
            walls: world
                .wall_contacts
                .iter()
                .filter(|w| p.id.binary_search(&w.id).is_ok_and(|i| owner[i] == r))
                .copied()
                .collect(),
        }
    }

    /// `parts` (each in id order) as one world's particles in id order, with the lasting
    /// contacts (renumbered; each part's in its order, parts in turn) and the walls' forces
    /// (sorted by particle and wall, their order in one process).
    pub fn merge(parts: Vec<Parcel>) -> Parcel {
        let mut merged = Parcel::default();
        let mut starts = Vec::with_capacity(parts.len());
        for (k, part) in parts.into_iter().enumerate() {
            starts.push(merged.particles.len());
            if k == 0 {
                merged.particles = part.particles;
            } else {
                merged.particles.append(&part.particles);
            }
            merged.lasting.extend(part.lasting);
            merged.walls.extend(part.walls);
        }
        let order = merged_order(&merged.particles.id, &starts);
        merged.particles = merged.particles.select(&order);
        merged.walls.sort_unstable_by_key(|c| (c.id, c.wall));
        merged
    }

    /// The lasting contacts renumbered to the indices of `particles`.
    pub fn renumbered(&self) -> Vec<LastingContact> {
        let ids = &self.particles.id;
        let index =
            |id: u32| ids.binary_search(&id).expect("a lasting contact's particles came with it") as u32;
        self.lasting.iter().map(|&([a, b], c)| LastingContact { a: index(a), b: index(b), ..c }).collect()
    }
}

/// The rows of `ids` in id order, where `ids` is runs each in id order starting at `starts`:
/// a merge of the runs (a frame gathers a million particles; a sort of them cost more than the
/// merge). A run out of order, which no caller makes, is sorted all the same.
fn merged_order(ids: &[u32], starts: &[usize]) -> Vec<usize> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let ends: Vec<usize> = starts.iter().skip(1).copied().chain([ids.len()]).collect();
    if starts.iter().zip(&ends).any(|(&a, &b)| !ids[a..b].is_sorted()) {
        let mut order: Vec<usize> = (0..ids.len()).collect();
        order.sort_unstable_by_key(|&i| ids[i]);
        return order;
    }
    let mut next: Vec<usize> = starts.to_vec();
    let mut heads: BinaryHeap<Reverse<(u32, usize)>> =
        (0..starts.len()).filter(|&r| next[r] < ends[r]).map(|r| Reverse((ids[next[r]], r))).collect();
    let mut order = Vec::with_capacity(ids.len());
    while let Some(Reverse((_, r))) = heads.pop() {
        order.push(next[r]);
        next[r] += 1;
        if next[r] < ends[r] {
            heads.push(Reverse((ids[next[r]], r)));
        }
    }
    order
}

/// A lasting contact with its particles named by id (indices change between ranks).
fn by_id(p: &Particles, c: &LastingContact) -> ([u32; 2], LastingContact) {
    ([p.id[c.a as usize], p.id[c.b as usize]], *c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_merge_of_id_ordered_parts_is_the_id_order_and_an_unordered_part_is_sorted() {
        // Three ranks' parts, each in id order, their ids interleaved; one part empty.
        let ids = [2, 5, 9, 1, 3, 4, 10, 0, 6];
        let order = merged_order(&ids, &[0, 3, 7, 7]);
        let merged: Vec<u32> = order.iter().map(|&i| ids[i]).collect();
        assert_eq!(merged, vec![0, 1, 2, 3, 4, 5, 6, 9, 10]);
        let unordered = [4, 1, 3, 0, 2];
        let order = merged_order(&unordered, &[0, 3]);
        assert_eq!(order.iter().map(|&i| unordered[i]).collect::<Vec<_>>(), vec![0, 1, 2, 3, 4]);
    }
}
