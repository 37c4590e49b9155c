//! Independent subtrees of a supernodal elimination tree, in two groups of about equal work.
//!
//! A supernode's factor columns depend only on its descendants, and in the forward solve it
//! updates only its ancestors. Two groups of disjoint whole subtrees can therefore be
//! factorised (and solved) side by side, and then the rest, their common ancestors, in order
//! (`incremental_cholesky`). The tree is postordered, so a subtree is a range of supernodes with
//! its root last, and its factor values are one contiguous slice.

use std::collections::BinaryHeap;
use std::ops::Range;

/// Below this total work (flops) one worker is faster than two: the split's own cost (a second
/// work space and solve buffer) is then a noticeable share.
const MIN_WORK: f64 = 1e7;
/// Splits that would not cut the time by this factor are not worth their buffers.
const MIN_GAIN: f64 = 1.2;

/// Two groups of whole subtrees (supernode ranges, ascending) and the supernodes in neither.
#[derive(Debug)]
pub(crate) struct Split {
    pub groups: [Vec<Range<usize>>; 2],
    /// The supernodes in no group, ascending: ancestors of the groups' subtrees.
    pub rest: Vec<usize>,
    /// Per column, 1 or 2 if a supernode of that group holds it, else 0.
    pub owner: Vec<u8>,
}

impl Split {
    /// The split of the tree with `parent[s]` (`root` for none; parents come after their
    /// children) and `work[s]` per supernode, whose supernode s holds the columns `cols(s)`; `None`
    /// if the tree is too small or too unbalanced to gain from it. Work below `min_work` is never
    /// split ([`MIN_WORK`] outside tests).
    pub fn new(
        parent: &[usize],
        work: &[f64],
        root: usize,
        cols: impl Fn(usize) -> Range<usize>,
        min_work: Option<f64>,
    ) -> Option<Split> {
        let n = parent.len();
        let mut sub = work.to_vec();
        let mut first: Vec<usize> = (0..n).collect();
        for s in 0..n {
            let p = parent[s];
            if p != root {
                sub[p] += sub[s];
                first[p] = first[p].min(first[s]);
            }
        }
        let (child_ptr, children) = crate::ordering::group_by(n, |emit| {
            (0..n)
                .filter(|&s| parent[s] != root)
                .for_each(|s| emit(parent[s], s))
        });
        let roots = (0..n).filter(|&s| parent[s] == root);
        let total: f64 = roots.clone().map(|s| sub[s]).sum();
        if total < min_work.unwrap_or(MIN_WORK) {
            return None;
        }
        // Split the heaviest subtree into its children while it holds over a quarter of the work,
        // so that the subtrees can be dealt to two groups evenly. Non-negative floats order like
        // their bits.
        let mut front: BinaryHeap<(u64, usize)> = roots.map(|s| (sub[s].to_bits(), s)).collect();
        let mut rest_work = 0.0;
        while let Some(&(_, h)) = front.peek() {
            let kids = &children[child_ptr[h]..child_ptr[h + 1]];
            if sub[h] <= total / 4.0 || kids.is_empty() {
                break;
            }
            front.pop();
            rest_work += work[h];
            front.extend(kids.iter().map(|&c| (sub[c].to_bits(), c)));
        }
        // Heaviest first, each to the lighter group.
        let mut groups = [Vec::new(), Vec::new()];
        let mut load = [0.0; 2];
        for (_, s) in front.into_sorted_vec().into_iter().rev() {
            let g = usize::from(load[1] < load[0]);
            load[g] += sub[s];
            groups[g].push(first[s]..s + 1);
        }
        if total < MIN_GAIN * (rest_work + load[0].max(load[1])) || groups[1].is_empty() {
            return None;
        }
        let mut owner = vec![0u8; cols(n.saturating_sub(1)).end];
        for (g, ranges) in groups.iter_mut().enumerate() {
            ranges.sort_by_key(|r| r.start);
            for r in ranges.iter() {
                owner[cols(r.start).start..cols(r.end - 1).end].fill(g as u8 + 1);
            }
        }
        let mut grouped = vec![false; n];
        groups
            .iter()
            .flatten()
            .for_each(|r| grouped[r.clone()].fill(true));
        let rest = (0..n).filter(|&s| !grouped[s]).collect();
        Some(Split {
            groups,
            rest,
            owner,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ROOT: usize = usize::MAX;

    #[test]
    fn subtrees_of_at_most_a_quarter_of_the_work_are_dealt_to_two_groups() {
        // 0,1 -> 2; 3,4 -> 5; 2,5 -> 6 (postordered), one column each. Total work 9: the
        // subtrees under 2 and 5 (4 each) hold over a quarter and are split into their leaves.
        let parent = [2, 2, 6, 5, 5, 6, ROOT];
        let work = [1.0, 1.0, 2.0, 1.0, 1.0, 2.0, 1.0];
        let split = Split::new(&parent, &work, ROOT, |s| s..s + 1, Some(0.0)).unwrap();
        assert_eq!(split.groups, [vec![1..2, 4..5], vec![0..1, 3..4]]);
        assert_eq!(split.rest, vec![2, 5, 6]);
        assert_eq!(split.owner, vec![2, 1, 0, 2, 1, 0, 0]);
    }

    #[test]
    fn a_chain_or_a_small_tree_is_not_split() {
        let chain = [1, 2, 3, ROOT];
        assert!(Split::new(&chain, &[1.0; 4], ROOT, |s| s..s + 1, Some(0.0)).is_none());
        let parent = [2, 2, ROOT];
        assert!(Split::new(&parent, &[1.0; 3], ROOT, |s| s..s + 1, None).is_none());
    }
}
