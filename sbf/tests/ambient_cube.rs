//! Ambient cube identities.
use crate::common;

use sbf::{AmbientCube, Basis};

/// Ambient cube: partition of unity |n|² = 1, one lobe per axis active.
#[test]
fn ambient_cube_partition_of_unity() {
    let mut w = [0.0; 6];
    for d in common::random_directions(17, 10_000) {
        AmbientCube.eval_into(d, &mut w);
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    }
}
