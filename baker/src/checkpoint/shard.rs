//! A shard's partial state on disk — the items one machine baked of a bake spread over
//! several (`baker --shard I/N`) — and the merge of all N shards into the whole bake's state.
//!
//! A shard bakes the blocks of items [`Partition::of`]`(I, N, items)` deals it, of every
//! set of targets (lightmap texels, then probes), for every pass, and holds only those: its
//! targets are the part ([`crate::accumulate::Targets::part`], the lightmap's from a layout
//! that keeps only their points, [`crate::layout::lightmap::Lightmap::build_part`]), so its
//! state, checkpoints and memory follow its share. Since a pass's result at an item depends
//! on (seed, item id, pass) only,
//! the N shards' items put together **are** the single bake's state, bit for bit on one
//! kind of engine ([`crate::accumulate::partition`]).
//!
//! The file holds no measurement of the run (no time, no device): the same shard baked
//! twice writes the same bytes, so a retried task is harmless. Format (little endian):
//! magic `SBFSHRD3`; u32 length and the UTF-8 JSON [`ShardHeader`] (the shard's index and
//! count, the bake spec's canonical JSON, and per set its name, content
//! fingerprint, item count, block, passes and lobes per basis); then per set, for the
//! set's owned items in order, the moments (six f64, three u64 counts) and per basis the
//! encoder states (as in a checkpoint); last the u64 FNV-1a of every byte before it.

use super::{read_encoder, read_moments, write_atomic, write_encoder, write_moments, Fnv, Reader};
use crate::accumulate::{BakeConfig, BakeState, Partition, Targets};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"SBFSHRD3";
/// The format before the header recorded the bake spec (it recorded arguments).
const MAGIC_V1: &[u8; 8] = b"SBFSHRD1";
/// The format whose fingerprints hashed the points themselves (before
/// [`crate::accumulate::Targets::identity`]).
const MAGIC_V2: &[u8; 8] = b"SBFSHRD2";

/// The file name of shard `index` of `count`.
pub fn file_name(index: usize, count: usize) -> String {
    format!("shard-{index}-of-{count}.sbfshard")
}

/// Bytes per item: the moments (six f64, three u64) and per basis the encoder (per lobe
/// four f32, then an f32 weight and a u64 count).
fn item_bytes(lobes: &[usize]) -> usize {
    72 + lobes.iter().map(|l| 16 * l + 12).sum::<usize>()
}

/// What a shard holds of one set of targets.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SetHeader {
    /// "lightmap" or "probes".
    pub what: String,
    /// [`super::content_fingerprint`] of the whole bake's set, hex.
    pub fingerprint: String,
    /// Items in the whole set.
    pub items: usize,
    /// Items per partition block.
    pub block: usize,
    pub passes: u64,
    /// Lobes per basis, in the bake's order.
    pub lobes: Vec<usize>,
}

/// A shard file's header.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardHeader {
    pub index: usize,
    pub count: usize,
    /// The bake spec's canonical serialisation (`run::BakeSpec`: what is baked, nothing
    /// of where or how it runs); `baker merge` rebuilds the bake from it.
    pub spec: serde_json::Value,
    pub sets: Vec<SetHeader>,
}

/// One set's state as a shard writes it: its name, fingerprint, part, the whole set's
/// item count, the lobes per basis and the part's state (its items, in order:
/// [`crate::accumulate::Targets::part`]; possibly none).
#[derive(Debug, Clone)]
pub struct SetState<'a> {
    pub what: &'a str,
    pub fingerprint: u64,
    pub part: Partition,
    pub items: usize,
    pub lobes: Vec<usize>,
    pub state: &'a BakeState,
}

/// Serialises a shard: its index, count and bake spec, and the owned items of `sets`.
/// Every set's state must hold its part's items.
pub fn to_bytes(index: usize, count: usize, spec: &serde_json::Value, sets: &[SetState]) -> Vec<u8> {
    for s in sets {
        assert_eq!(
            s.state.moments.len(),
            s.part.share(s.items),
            "{}: the state holds other items than part {} of {}",
            s.what,
            index,
            count
        );
    }
    let header = ShardHeader {
        index,
        count,
        spec: spec.clone(),
        sets: sets
            .iter()
            .map(|s| SetHeader {
                what: s.what.to_string(),
                fingerprint: format!("{:016x}", s.fingerprint),
                items: s.items,
                block: s.part.block,
                passes: s.state.passes,
                lobes: s.lobes.clone(),
            })
            .collect(),
    };
    let json = serde_json::to_vec(&header).expect("a shard header serialises");
    let body: usize = sets.iter().map(|s| s.state.moments.len() * item_bytes(&s.lobes)).sum();
    let mut v = Vec::with_capacity(20 + json.len() + body);
    v.extend_from_slice(MAGIC);
    v.extend_from_slice(&(json.len() as u32).to_le_bytes());
    v.extend_from_slice(&json);
    for s in sets {
        s.state.moments.iter().for_each(|m| write_moments(&mut v, m));
        for encs in &s.state.encoders {
            encs.iter().for_each(|e| write_encoder(&mut v, e));
        }
    }
    let mut h = Fnv::default();
    h.bytes(&v);
    v.extend_from_slice(&h.finish().to_le_bytes());
    v
}

/// Writes a shard file atomically (a killed shard leaves no torn file).
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    write_atomic(path, bytes)
}

/// A shard file read back: its header and its item data (checked against the checksum).
#[derive(Debug, Clone)]
pub struct Shard {
    pub path: PathBuf,
    pub header: ShardHeader,
    body: Vec<u8>,
}

impl Shard {
    /// Reads and checks a shard file; errors name the file.
    pub fn read(path: &Path) -> Result<Shard, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Shard::from_bytes(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
    }

    fn from_bytes(path: &Path, bytes: Vec<u8>) -> Result<Shard, String> {
        if bytes.get(..8) == Some(MAGIC_V1.as_slice()) {
            return Err("a shard of an older baker (its header records arguments, not a bake spec): bake the shard again".into());
        }
        if bytes.get(..8) == Some(MAGIC_V2.as_slice()) {
            return Err("a shard of an earlier baker, whose bake identity was computed otherwise: bake the shard again".into());
        }
        if bytes.len() < 20 || &bytes[..8] != MAGIC {
            return Err("not a baker shard file (bad magic)".into());
        }
        let (data, sum) = bytes.split_at(bytes.len() - 8);
        let mut h = Fnv::default();
        h.bytes(data);
        if h.finish().to_le_bytes() != sum {
            return Err("checksum mismatch: the file is truncated or corrupt".into());
        }
        let len = u32::from_le_bytes(data[8..12].try_into().expect("4 bytes")) as usize;
        let json = data.get(12..12 + len).ok_or("header truncated")?;
        let header: ShardHeader = serde_json::from_slice(json).map_err(|e| format!("header: {e}"))?;
        if header.count == 0 || header.index >= header.count {
            return Err(format!("shard index {} of {} is invalid", header.index, header.count));
        }
        let mut expected = 0;
        for s in &header.sets {
            let part = Partition::with_block(header.index, header.count, s.block)?;
            expected += part.share(s.items) * item_bytes(&s.lobes);
        }
        if data.len() - 12 - len != expected {
            return Err(format!("holds {} bytes of items, its header describes {expected}", data.len() - 12 - len));
        }
        Ok(Shard { path: path.to_path_buf(), header, body: data[12 + len..].to_vec() })
    }

    /// The shard's name for messages: "shard I of N (FILE)".
    pub fn name(&self) -> String {
        format!("shard {} of {} ({})", self.header.index, self.header.count, self.path.display())
    }

    /// Copies this shard's items of set `set` into `state`, after checking the set is the
    /// one `fingerprint`, `config` and `targets` describe.
    fn fill(&self, set: usize, fingerprint: u64, config: &BakeConfig, targets: &Targets, state: &mut BakeState) -> Result<(), String> {
        let mut r = Reader { b: &self.body, at: 0 };
        for s in &self.header.sets[..set] {
            let part = Partition::with_block(self.header.index, self.header.count, s.block)?;
            r.take(part.share(s.items) * item_bytes(&s.lobes))?;
        }
        let h = &self.header.sets[set];
        let n = targets.items.len();
        if h.fingerprint != format!("{fingerprint:016x}") {
            return Err(format!(
                "{}: its {} belongs to another bake (fingerprint {}, this bake {fingerprint:016x}): the scene content, layout, probe positions, seed, bounces, bases, solver or sample sequence differ",
                self.name(),
                h.what,
                h.fingerprint
            ));
        }
        let lobes: Vec<usize> = config.bases.iter().map(|b| b.lobes()).collect();
        if h.items != n || h.lobes != lobes {
            return Err(format!("{}: its {} has {} items × lobes {:?}, this bake {n} × {lobes:?}", self.name(), h.what, h.items, h.lobes));
        }
        let part = Partition::with_block(self.header.index, self.header.count, h.block)?;
        for k in part.ranges(n).flatten() {
            state.moments[k] = read_moments(&mut r)?;
        }
        for (b, encs) in state.encoders.iter_mut().enumerate() {
            let opts = config.encoder_options(config.bases[b], targets.sphere);
            for k in part.ranges(n).flatten() {
                encs[k] = read_encoder(&mut r, &opts, lobes[b])?;
            }
        }
        Ok(())
    }
}

/// Checks that `shards` are exactly shards 0..N of one split, each once; errors name the
/// files of a different split, the duplicates and the missing indices.
pub fn check_complete(shards: &[Shard]) -> Result<usize, String> {
    let first = shards.first().ok_or("no shard files given")?;
    let n = first.header.count;
    if let Some(s) = shards.iter().find(|s| s.header.count != n) {
        return Err(format!("{} and {} are of different splits (into {n} and {} shards)", first.name(), s.name(), s.header.count));
    }
    let mut by_index: Vec<Option<&Shard>> = vec![None; n];
    for s in shards {
        if let Some(other) = by_index[s.header.index] {
            return Err(format!("shard {} of {n} is given twice: {} and {}", s.header.index, other.path.display(), s.path.display()));
        }
        by_index[s.header.index] = Some(s);
    }
    let missing: Vec<String> = (0..n).filter(|&i| by_index[i].is_none()).map(|i| i.to_string()).collect();
    if !missing.is_empty() {
        let given: Vec<String> = (0..n).filter(|&i| by_index[i].is_some()).map(|i| i.to_string()).collect();
        let flags: Vec<String> = missing.iter().map(|i| format!("--shard {i}/{n}")).collect();
        return Err(format!(
            "missing shard{} {} of {n} (given: {}); bake {} with {}",
            if missing.len() > 1 { "s" } else { "" },
            missing.join(", "),
            given.join(", "),
            if missing.len() > 1 { "them" } else { "it" },
            flags.join(", ")
        ));
    }
    Ok(n)
}

/// The whole bake's state of set `set` ("lightmap", "probes"), each item from the shard
/// that baked it. `shards` must pass [`check_complete`]; every shard's set must be the one
/// `fingerprint`, `config` and `targets` describe, run for the same passes.
pub fn merge(shards: &[Shard], set: usize, fingerprint: u64, config: &BakeConfig, targets: &Targets) -> Result<BakeState, String> {
    let mut state = BakeState::new(config, targets);
    let mut passes = None;
    for s in shards {
        let h = s
            .header
            .sets
            .get(set)
            .ok_or_else(|| format!("{}: holds {} sets of targets, not {}", s.name(), s.header.sets.len(), set + 1))?;
        match passes {
            None => passes = Some((h.passes, s)),
            Some((p, first)) if p != h.passes => {
                return Err(format!("{} ran {} passes of its {}, {} ran {p}", s.name(), h.passes, h.what, first.name()));
            }
            Some(_) => {}
        }
        s.fill(set, fingerprint, config, targets, &mut state)?;
    }
    state.passes = passes.map_or(0, |p| p.0);
    Ok(state)
}
