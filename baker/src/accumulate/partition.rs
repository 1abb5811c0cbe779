//! How a bake's items (texels or probes) are dealt out to the engines that bake them in
//! parallel: the GPUs of one host ([`crate::gpu::multi`]) and the shards of a bake spread
//! over machines (`baker --shard I/N`, merged by `baker merge`).
//!
//! Items are dealt in blocks of consecutive items, block b to part b mod N (interleaved, so
//! every part gets a like share of bright and dark, simple and deep regions: contiguous
//! halves of an atlas differ in cost — 1.74× on two H200s for the fair scene). A pass's
//! result at an item depends on (seed, item, pass) only, never on which part computes it,
//! so the parts' states, each item taken from the part that baked it, are the whole bake's
//! state bit for bit on one kind of engine.
//!
//! A `baker --shard I/N` run holds only its part's items ([`crate::accumulate::Targets::part`]),
//! in order, and deals them to its GPUs as a single bake deals its atlas. A bake that keeps
//! every item can split a part's blocks again instead: device g of part I of N bakes the
//! blocks b with b mod N·G = I + N·g ([`Partition::split`], `MultiGpuBake::for_part`).
//! Either way each item's result is the same: it depends on (seed, item id, pass) only.

/// The partition block for `items` dealt to `parts`: about 32 blocks per part (a balanced
/// share whatever the atlas's layout) of a multiple of 64 items (whole GPU workgroups), 64
/// to 4096 (long runs of neighbouring texels keep the BVH traversal coherent).
pub fn partition_block(items: usize, parts: usize) -> usize {
    (items / (32 * parts.max(1)) / 64).clamp(1, 64) * 64
}

/// The part of `parts` that bakes `item` with blocks of `block` items.
pub fn owner(item: usize, block: usize, parts: usize) -> usize {
    (item / block) % parts
}

/// One part of a dealing: the blocks b of `block` items with b mod `count` = `index`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Partition {
    pub index: usize,
    pub count: usize,
    pub block: usize,
}

impl Partition {
    /// Part `index` of `count` of `items` items, blocks of [`partition_block`].
    pub fn of(index: usize, count: usize, items: usize) -> Result<Partition, String> {
        Partition::with_block(index, count, partition_block(items, count))
    }

    /// Part `index` of `count` with blocks of `block` items.
    pub fn with_block(index: usize, count: usize, block: usize) -> Result<Partition, String> {
        if count == 0 || index >= count || block == 0 || block > u32::MAX as usize || count > u32::MAX as usize {
            return Err(format!("part {index} of {count} with blocks of {block} items is invalid"));
        }
        Ok(Partition { index, count, block })
    }

    /// Whether this part bakes `item`.
    pub fn owns(&self, item: usize) -> bool {
        owner(item, self.block, self.count) == self.index
    }

    /// The item ranges this part bakes out of `items`, in order.
    pub fn ranges(&self, items: usize) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
        (self.index * self.block..items).step_by(self.count * self.block).map(move |s| s..(s + self.block).min(items))
    }

    /// How many of `items` items this part bakes.
    pub fn share(&self, items: usize) -> usize {
        self.ranges(items).map(|r| r.len()).sum()
    }

    /// Part `g` of `parts` of this part's blocks, dealt round-robin: the blocks b with
    /// b mod count·parts = index + count·g (same block size).
    pub fn split(&self, g: usize, parts: usize) -> Partition {
        Partition { index: self.index + self.count * g, count: self.count * parts, block: self.block }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The split of a shard's blocks among its devices covers exactly the shard's items,
    /// each once (the identity b mod N·G = I + N·g ⇔ b mod N = I and ⌊b/N⌋ mod G = g).
    #[test]
    fn a_split_shard_covers_its_items_once() {
        for (items, n, gpus) in [(10_000usize, 3usize, 2usize), (777, 7, 3), (64, 2, 2), (5_000, 1, 4)] {
            for i in 0..n {
                let shard = Partition::of(i, n, items).unwrap();
                let mut seen = vec![0u8; items];
                for g in 0..gpus {
                    for r in shard.split(g, gpus).ranges(items) {
                        r.for_each(|k| seen[k] += 1);
                    }
                }
                for (k, s) in seen.iter().enumerate() {
                    assert_eq!(*s as usize, shard.owns(k) as usize, "{items} items, shard {i}/{n}, {gpus} GPUs: item {k}");
                }
                assert_eq!(shard.share(items), (0..items).filter(|&k| shard.owns(k)).count());
            }
        }
    }
}
