//! Islands: particles that may touch each other in the step, connected by candidate pairs
//! (union–find); a wall candidate outside every pair is an island of one.

use crate::contact::FastMap;

/// A group of particles resolved together: its members (particle indices, ascending) and its
/// candidate pairs as positions among the members (lower first).
pub(crate) struct Island {
    pub members: Vec<usize>,
    pub pairs: Vec<[usize; 2]>,
}

/// Groups particles connected by candidate pairs; every wall candidate outside a pair is an
/// island of one. Islands come in order of their lowest particle index.
pub(crate) fn islands(wall_candidates: &[u32], pairs: &[[u32; 2]]) -> Vec<Island> {
    let mut parent: FastMap<u32, u32> = FastMap::default();
    fn root(parent: &mut FastMap<u32, u32>, i: u32) -> u32 {
        let mut r = i;
        while let Some(&up) = parent.get(&r) {
            if up == r {
                break;
            }
            r = up;
        }
        parent.insert(i, r);
        r
    }
    for &[a, b] in pairs {
        parent.entry(a).or_insert(a);
        parent.entry(b).or_insert(b);
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        if ra != rb {
            parent.insert(ra.max(rb), ra.min(rb));
        }
    }
    let mut groups: FastMap<u32, Vec<usize>> = FastMap::default();
    let members: Vec<u32> = parent.keys().copied().collect();
    for i in members {
        let r = root(&mut parent, i);
        groups.entry(r).or_default().push(i as usize);
    }
    let mut out: Vec<Island> = groups
        .into_values()
        .map(|mut members| {
            members.sort_unstable();
            Island { members, pairs: Vec::new() }
        })
        .collect();
    out.sort_unstable_by_key(|island| island.members[0]);
    let mut island_of: FastMap<usize, usize> = FastMap::default();
    for (k, island) in out.iter().enumerate() {
        for &i in &island.members {
            island_of.insert(i, k);
        }
    }
    for &[a, b] in pairs {
        let k = island_of[&(a as usize)];
        let m = &out[k].members;
        let pos = |i: u32| m.binary_search(&(i as usize)).expect("member");
        let local = [pos(a), pos(b)];
        out[k].pairs.push(local);
    }
    for &i in wall_candidates {
        if !island_of.contains_key(&(i as usize)) {
            out.push(Island { members: vec![i as usize], pairs: Vec::new() });
        }
    }
    out.sort_unstable_by_key(|island| island.members[0]);
    out
}
