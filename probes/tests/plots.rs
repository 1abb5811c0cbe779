//! The plots' pieces: readable tick labels, the Pareto front against brute force, and
//! label placement without overlaps.

use probes::images::{front, place_labels, tick};
use sbf::sampling::Pcg32;

#[test]
fn ticks_are_plain_numbers() {
    for (v, want) in [
        (100.0, "100"),
        (0.02, "0.02"),
        (0.001, "0.001"),
        (1.5, "1.5"),
        (12.5, "12.5"),
        (99999.0, "99999"),
        (2.5e-5, "2.5e-5"),
        (1e6, "1e6"),
        (0.000999, "9.99e-4"),
        (0.1234, "0.123"),
    ] {
        assert_eq!(tick(v), want, "{v}");
    }
}

/// Every front point is beaten by no point on both axes; every other point is beaten (or
/// equalled) by a front point. Random clouds with ties.
#[test]
fn front_matches_brute_force() {
    let mut r = Pcg32::new(3, 9);
    for _ in 0..200 {
        let n = 1 + (r.next_u32() % 30) as usize;
        let pts: Vec<(f64, f64)> = (0..n).map(|_| (((r.next_u32() % 8) + 1) as f64, ((r.next_u32() % 8) + 1) as f64)).collect();
        let f = front(&pts);
        let beats = |a: (f64, f64), b: (f64, f64)| a.0 <= b.0 && a.1 <= b.1 && (a.0 < b.0 || a.1 < b.1);
        for i in 0..n {
            let dominated = pts.iter().any(|o| beats(*o, pts[i]));
            if f.contains(&i) {
                assert!(!dominated, "{pts:?}: {i} on the front but dominated");
            } else {
                assert!(dominated || f.iter().any(|j| pts[*j] == pts[i]), "{pts:?}: {i} missing");
            }
        }
        assert!(f.windows(2).all(|w| pts[w[0]].0 <= pts[w[1]].0 && pts[w[0]].1 > pts[w[1]].1), "ordered by cost, error falling");
    }
}

/// Placed labels (7 px per character, 14 px high) overlap neither each other nor any point
/// marker (8 px square), on crowded random layouts.
#[test]
fn labels_do_not_overlap() {
    let mut r = Pcg32::new(1, 2);
    let mut unplaced = 0;
    let mut total = 0;
    for _ in 0..100 {
        let n = 5 + (r.next_u32() % 25) as usize;
        let px: Vec<(i32, i32)> = (0..n).map(|_| ((r.next_u32() % 600) as i32, (r.next_u32() % 400) as i32)).collect();
        let labels: Vec<String> = (0..n).map(|i| format!("mode{i}")).collect();
        let placed = place_labels(&px, &labels);
        let mut boxes: Vec<(i32, i32, i32, i32)> = px.iter().map(|p| (p.0 - 4, p.1 - 4, p.0 + 4, p.1 + 4)).collect();
        for ((p, l), o) in px.iter().zip(&labels).zip(&placed) {
            total += 1;
            let Some((dx, dy)) = o else {
                unplaced += 1;
                continue;
            };
            let w = 7 * l.chars().count() as i32 + 2;
            let b = (p.0 + dx, p.1 + dy, p.0 + dx + w, p.1 + dy + 14);
            assert!(!boxes.iter().any(|o| o.0 < b.2 && b.0 < o.2 && o.1 < b.3 && b.1 < o.3), "label {l} overlaps");
            boxes.push(b);
        }
    }
    println!("{unplaced} of {total} labels found no free place");
    assert!(unplaced * 5 < total, "most labels must find a place ({unplaced} of {total} did not)");
}

/// Thumbnails (PNG previews, the interactive view's data): box filtering by 2^k to the
/// width limit keeps every block's mean — checked block by block against a direct sum on a
/// random 512 × 256 image — and leaves narrow images alone.
#[test]
fn box_shrink_averages_blocks() {
    use probes::images::box_shrink;
    use sbf::envmap::LatLong;
    let mut r = Pcg32::new(8, 8);
    let g = LatLong { width: 512, height: 256 };
    let px: Vec<[f64; 3]> = (0..g.width * g.height).map(|_| [r.next_f64(), r.next_f64() * 10.0, 0.5]).collect();
    let (s, out) = box_shrink(g, &px, 256);
    assert_eq!((s.width, s.height), (256, 128));
    for (k, o) in out.iter().enumerate() {
        let (i, j) = (k % 256, k / 256);
        let want: Vec<f64> = (0..3).map(|c| (0..4).map(|q| px[(2 * j + q / 2) * 512 + 2 * i + q % 2][c]).sum::<f64>() / 4.0).collect();
        for c in 0..3 {
            assert!((o[c] - want[c]).abs() <= 1e-15 * want[c].abs().max(1.0), "block ({i}, {j})");
        }
    }
    let (s, out) = box_shrink(g, &px, 64);
    assert_eq!((s.width, s.height, out.len()), (64, 32, 64 * 32));
    let (s, same) = box_shrink(LatLong { width: 64, height: 32 }, &px[..2048], 256);
    assert_eq!((s.width, s.height), (64, 32));
    assert_eq!(same, px[..2048].to_vec());
}
