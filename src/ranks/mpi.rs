//! The [`Comm`] of a run under `mpirun`: MPI's world communicator (rsmpi over the system's
//! Open MPI; `--features mpi`).

use super::comm::Comm;
use mpi::Count;
use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// MPI, initialised for this process: its world communicator. Dropping it finalises MPI.
pub struct Mpi {
    // The world before the universe: it is freed first.
    world: SimpleCommunicator,
    _universe: Universe,
}

impl Mpi {
    /// Initialises MPI (once per process). Every call comes from the thread that initialised
    /// it: the run's own thread (`Funneled`). A binary started without `mpirun` is a world of
    /// one rank (Open MPI's singleton).
    pub fn init() -> Option<Mpi> {
        let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Funneled)?;
        let world = universe.world();
        Some(Mpi { world, _universe: universe })
    }
}

/// The offsets of parts of the given lengths laid end to end, and their total.
fn displacements(counts: &[Count]) -> (Vec<Count>, usize) {
    let mut at = 0;
    let displs = counts
        .iter()
        .map(|&c| {
            let d = at;
            at += c;
            d
        })
        .collect();
    (displs, at as usize)
}

/// A buffer of `len` bytes, never of no memory: an empty `Vec`'s pointer is 1, which Open MPI reads
/// as `MPI_IN_PLACE` ("MPI_ERR_ARG" from `MPI_Alltoallv` when a rank receives nothing).
fn room(len: usize) -> Vec<u8> {
    vec![0u8; len.max(1)]
}

fn split(buffer: &[u8], counts: &[Count], displs: &[Count]) -> Vec<Vec<u8>> {
    counts.iter().zip(displs).map(|(&c, &d)| buffer[d as usize..(d + c) as usize].to_vec()).collect()
}

/// A message's length as MPI counts it: the run stops if one part passes 2 GiB (MPI's `int`).
fn count(len: usize) -> Count {
    Count::try_from(len).expect("a message to one rank under 2 GiB (MPI counts are 32-bit)")
}

impl Comm for Mpi {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.world.size() as usize
    }

    fn all_gather(&self, bytes: &[u8]) -> Vec<Vec<u8>> {
        let mut counts = vec![0 as Count; self.size()];
        self.world.all_gather_into(&count(bytes.len()), &mut counts[..]);
        let (displs, total) = displacements(&counts);
        let mut buffer = room(total);
        let none = room(0);
        let send = if bytes.is_empty() { &none[..0] } else { bytes };
        {
            let mut parts = PartitionMut::new(&mut buffer[..], &counts[..], &displs[..]);
            self.world.all_gather_varcount_into(send, &mut parts);
        }
        split(&buffer, &counts, &displs)
    }

    fn exchange(&self, outgoing: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        let send_counts: Vec<Count> = outgoing.iter().map(|m| count(m.len())).collect();
        let mut recv_counts = vec![0 as Count; self.size()];
        self.world.all_to_all_into(&send_counts[..], &mut recv_counts[..]);
        let (send_displs, _) = displacements(&send_counts);
        let mut send: Vec<u8> = outgoing.concat();
        if send.is_empty() {
            send = Vec::with_capacity(1);
        }
        let (recv_displs, total) = displacements(&recv_counts);
        let mut buffer = room(total);
        {
            let parts = Partition::new(&send[..], &send_counts[..], &send_displs[..]);
            let mut into = PartitionMut::new(&mut buffer[..], &recv_counts[..], &recv_displs[..]);
            self.world.all_to_all_varcount_into(&parts, &mut into);
        }
        split(&buffer, &recv_counts, &recv_displs)
    }

    fn max(&self, x: f64) -> f64 {
        let mut out = 0.0;
        self.world.all_reduce_into(&x, &mut out, SystemOperation::max());
        out
    }

    fn any(&self, b: bool) -> bool {
        let mut out = 0i32;
        self.world.all_reduce_into(&(b as i32), &mut out, SystemOperation::max());
        out != 0
    }

    fn abandon(&self, code: i32) {
        self.world.abort(code)
    }
}
