//! Disjoint sets as a parent array (`parent[i] == i` at a root): the one
//! home of the root lookup that connected components (mesh shells, cloud
//! voxels, arrangement regions, overlapping balls) are built from. Each
//! caller links roots its own way.

/// The root of `i`'s set, halving the path on the way (every node visited
/// is linked to its grandparent).
pub fn root(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let up = parent[parent[i as usize] as usize];
        parent[i as usize] = up;
        i = up;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chain_has_one_root_and_its_path_is_halved() {
        // 4 -> 3 -> 2 -> 1 -> 0
        let mut parent = vec![0, 0, 1, 2, 3, 5];
        assert_eq!(root(&mut parent, 4), 0);
        // 4 now points at 2 and 2 at 0: every other link skipped.
        assert_eq!(parent, vec![0, 0, 0, 2, 2, 5]);
        assert_eq!(root(&mut parent, 4), 0);
        assert_eq!(root(&mut parent, 5), 5);
    }
}
