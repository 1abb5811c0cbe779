//! A run-wide memo: a value computed once per key, shared by the threads that ask for it
//! (the first computes, the others wait for it). Used for work several modes share, e.g.
//! the per-lobe specular responses of one lobe layout at one roughness.

use std::sync::{Arc, Mutex, OnceLock};

/// Values by key, each computed at most once.
#[derive(Debug, Default)]
pub struct Memo<V> {
    slots: Mutex<Vec<(String, Arc<OnceLock<V>>)>>,
}

impl<V> Memo<V> {
    pub fn new() -> Memo<V> {
        Memo { slots: Mutex::new(Vec::new()) }
    }

    /// The value of `key`, computed by `f` if no thread has yet. `f` must not use rayon or
    /// ask this memo for the same key: other threads asking for the key block until it
    /// returns, and a thread waiting inside rayon may pick up a task that asks for the key
    /// it is computing (a deadlock).
    pub fn get(&self, key: &str, f: impl FnOnce() -> V) -> Arc<OnceLock<V>> {
        let slot = {
            let mut slots = self.slots.lock().unwrap_or_else(|e| e.into_inner());
            match slots.iter().find(|(k, _)| k == key) {
                Some((_, s)) => s.clone(),
                None => {
                    let s = Arc::new(OnceLock::new());
                    slots.push((key.to_string(), s.clone()));
                    s
                }
            }
        };
        slot.get_or_init(f);
        slot
    }
}
