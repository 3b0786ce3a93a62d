//! The few collective operations a run on several ranks needs, on bytes: an MPI communicator
//! (`--features mpi`, [`super::mpi`]), threads of one process standing in for ranks
//! ([`Threads`]: the tests of the exchange, on any machine), or one process alone.
//!
//! Everything a rank sends is serialised with postcard first (the checkpoints' format), so the
//! ranks exchange only byte strings and MPI needs no datatype of ours.

use serde::Serialize;
use serde::de::DeserializeOwned;
use std::sync::{Arc, Barrier, Mutex};

/// A communicator between the ranks of one run. Every rank calls the same operations in the
/// same order (they are collective: one that is skipped on a rank hangs the others).
pub trait Comm {
    /// This rank's number, from 0.
    fn rank(&self) -> usize;
    /// How many ranks the run has.
    fn size(&self) -> usize;
    /// Every rank's `bytes`, on every rank, in rank order.
    fn all_gather(&self, bytes: &[u8]) -> Vec<Vec<u8>>;
    /// Sends `outgoing[r]` to rank `r` (one entry per rank, this one's included); returns what
    /// each rank sent to this one, in rank order.
    fn exchange(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>>;
    /// The largest of every rank's `x`.
    fn max(&self, x: f64) -> f64 {
        let all = self.all_gather(&x.to_le_bytes());
        all.iter()
            .map(|b| f64::from_le_bytes(b[..8].try_into().expect("8 bytes")))
            .fold(f64::NEG_INFINITY, f64::max)
    }
    /// Whether `b` holds on any rank.
    fn any(&self, b: bool) -> bool {
        self.all_gather(&[b as u8]).iter().any(|v| v[0] != 0)
    }
    /// Ends the whole run, every rank, with exit status `code`: what a rank that cannot go on
    /// does once its files are finished, so that the others do not wait for it forever. Threads
    /// and one process have nothing to end.
    fn abandon(&self, _code: i32) {}
}

/// Serialises `value` for a [`Comm`]. Our own plain data: serialising it cannot fail short of
/// memory, which aborts anyway.
pub fn encode<T: Serialize + ?Sized>(value: &T) -> Vec<u8> {
    postcard::to_stdvec(value).expect("postcard serialises plain data")
}

/// Reads what [`encode`] wrote on another rank of the same binary.
pub fn decode<T: DeserializeOwned>(bytes: &[u8]) -> T {
    postcard::from_bytes(bytes).expect("the same binary on every rank reads its own encoding")
}

/// Every rank's `value`, in rank order.
pub fn all_gather<T: Serialize + DeserializeOwned>(comm: &dyn Comm, value: &T) -> Vec<T> {
    comm.all_gather(&encode(value)).iter().map(|b| decode(b)).collect()
}

/// What every rank sent to this one, each `outgoing[r]` going to rank `r`.
pub fn exchange<T: Serialize + DeserializeOwned>(comm: &dyn Comm, outgoing: &[T]) -> Vec<T> {
    comm.exchange(outgoing.iter().map(|v| encode(v)).collect()).iter().map(|b| decode(b)).collect()
}

/// One process: rank 0 of 1.
#[derive(Debug, Default, Clone, Copy)]
pub struct Alone;

impl Comm for Alone {
    fn rank(&self) -> usize {
        0
    }
    fn size(&self) -> usize {
        1
    }
    fn all_gather(&self, bytes: &[u8]) -> Vec<Vec<u8>> {
        vec![bytes.to_vec()]
    }
    fn exchange(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        outgoing
    }
}

/// Ranks as threads of one process, for tests: each thread holds one [`Threads`] of a set made
/// by [`Threads::set`]. Collectives meet at a barrier.
#[derive(Debug, Clone)]
pub struct Threads {
    rank: usize,
    shared: Arc<Shared>,
}

#[derive(Debug)]
struct Shared {
    barrier: Barrier,
    /// `slots[from][to]`: what rank `from` sends to rank `to` in the current collective.
    slots: Mutex<Vec<Vec<Vec<u8>>>>,
}

impl Threads {
    /// `size` communicators, one per thread-rank.
    pub fn set(size: usize) -> Vec<Threads> {
        let shared = Arc::new(Shared {
            barrier: Barrier::new(size),
            slots: Mutex::new(vec![vec![Vec::new(); size]; size]),
        });
        (0..size).map(|rank| Threads { rank, shared: shared.clone() }).collect()
    }
}

impl Comm for Threads {
    fn rank(&self) -> usize {
        self.rank
    }
    fn size(&self) -> usize {
        self.shared.barrier_size()
    }
    fn all_gather(&self, bytes: &[u8]) -> Vec<Vec<u8>> {
        self.exchange(vec![bytes.to_vec(); self.size()])
    }
    fn exchange(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        let n = self.size();
        assert_eq!(outgoing.len(), n, "one message per rank");
        self.shared.slots.lock().expect("no rank panicked")[self.rank] = outgoing;
        self.shared.barrier.wait();
        let incoming = (0..n)
            .map(|from| self.shared.slots.lock().expect("no rank panicked")[from][self.rank].clone())
            .collect();
        // Nobody writes the slots of the next collective before everyone has read these.
        self.shared.barrier.wait();
        incoming
    }
}

impl Shared {
    fn barrier_size(&self) -> usize {
        self.slots.lock().expect("no rank panicked").len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_ranks_gather_and_exchange_in_rank_order() {
        let set = Threads::set(3);
        let handles: Vec<_> = set
            .into_iter()
            .map(|c| {
                std::thread::spawn(move || {
                    let r = c.rank() as u32;
                    let gathered: Vec<u32> = all_gather(&c, &r);
                    let sent: Vec<(u32, u32)> = (0..3).map(|to| (r, to)).collect();
                    let got: Vec<(u32, u32)> = exchange(&c, &sent);
                    (gathered, got, c.max(r as f64), c.any(r == 2))
                })
            })
            .collect();
        for (rank, h) in handles.into_iter().enumerate() {
            let (gathered, got, max, any) = h.join().unwrap();
            assert_eq!(gathered, vec![0, 1, 2]);
            assert_eq!(got, (0..3).map(|from| (from, rank as u32)).collect::<Vec<_>>());
            assert_eq!((max, any), (2.0, true));
        }
    }
}
