//! The fixed reduction order of the Monte Carlo statistics: a dyadic tree over absolute block
//! indices, so that any cut of the blocks into contiguous shards merges back to the same bits.
//!
//! Chan's merge is exact algebra but not associative in floating point, so the order of merges is
//! part of the result. A left fold over blocks cannot be split and re-joined bit-identically; the
//! tree can: node (ℓ, i) covers blocks [i·2^ℓ, (i+1)·2^ℓ) and is always the merge of its two
//! children, so its value does not depend on who computed it. Blocks (level 0) are pushed in
//! index order; a node whose left sibling is on top of the stack is merged with it, repeatedly.
//! After blocks [0, j) the stack is the binary decomposition of j, whoever pushed them: a shard
//! covering [a, b) keeps its own stack of maximal aligned nodes (O(log) of them), and pushing
//! every shard's nodes in block order rebuilds the one-machine stack exactly. The remaining stack
//! is folded left to right (`Tree::finish`).

use crate::sim::mc_stats::McStats;

/// One node of the tree: the merged statistics of blocks [index·2^level, (index+1)·2^level).
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub level: u32,
    pub index: u64,
    pub stats: McStats,
}

impl Node {
    /// The blocks it covers.
    pub fn blocks(&self) -> std::ops::Range<u64> {
        let width = 1u64 << self.level;
        self.index * width..(self.index + 1) * width
    }
}

/// The stack of unmerged nodes.
#[derive(Debug, Default)]
pub(crate) struct Tree {
    stack: Vec<Node>,
}

impl Tree {
    /// Pushes the next node in block order, merging it with its left sibling while it has one on
    /// top of the stack.
    pub fn push(&mut self, mut node: Node) {
        while let Some(top) = self.stack.last() {
            if top.level != node.level || top.index % 2 != 0 || top.index + 1 != node.index {
                break;
            }
            let mut left = self.stack.pop().expect("a top");
            left.stats.merge(&node.stats);
            node = Node { level: left.level + 1, index: left.index / 2, stats: left.stats };
        }
        self.stack.push(node);
    }

    /// The nodes still on the stack, in block order: what a shard hands on.
    pub(crate) fn into_nodes(self) -> Vec<Node> {
        self.stack
    }

    /// The whole statistics: the stack folded left to right onto `empty()`. The first node is the
    /// start of the fold instead of being merged into a fresh `empty()`: merging into empty
    /// accumulators copies every one bit for bit, but a fresh copy would hold a second set of
    /// per-step accumulators (102 MB at N = 10⁶ with 2 filters) while the first is still alive.
    pub fn finish(self, empty: impl FnOnce() -> McStats) -> McStats {
        let mut nodes = self.stack.into_iter();
        let Some(first) = nodes.next() else { return empty() };
        let mut acc = first.stats;
        for f in &mut acc.filters {
            // As `McStats::merge` into a fresh 0.0 takes it (`f64::max` drops a NaN).
            f.max_ratio = 0.0f64.max(f.max_ratio);
        }
        for n in nodes {
            acc.merge(&n.stats);
        }
        acc
    }

    /// Rebuilds the tree from nodes given in block order (every shard's, shard after shard).
    pub(crate) fn from_nodes(nodes: impl IntoIterator<Item = Node>) -> Self {
        let mut t = Tree::default();
        for n in nodes {
            t.push(n);
        }
        t
    }
}
