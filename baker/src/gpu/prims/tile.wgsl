// Tile-format indices ([Roughton19], §5.2): texel (x, y) of a grid `tiles_per_row` tiles wide,
// tiles of n × n texels (n a power of two, log2_n = log2(n)):
// T = (⌊x/n⌋ + tiles_per_row·⌊y/n⌋) << log2(n²) | ((x mod n) + n·(y mod n))   (eq. 5.2),
// and its inverse (eq. 5.3 gives the tile's origin; the low bits the texel within it).

fn tile_index(x: u32, y: u32, log2_n: u32, tiles_per_row: u32) -> u32 {
    let n = 1u << log2_n;
    let tile = (x >> log2_n) + tiles_per_row * (y >> log2_n);
    return (tile << (2u * log2_n)) | ((x & (n - 1u)) + (n * (y & (n - 1u))));
}

fn tile_coords(i: u32, log2_n: u32, tiles_per_row: u32) -> vec2<u32> {
    let n = 1u << log2_n;
    let tile = i >> (2u * log2_n);
    let within = i & (n * n - 1u);
    return vec2<u32>(n * (tile % tiles_per_row) + (within & (n - 1u)), n * (tile / tiles_per_row) + (within >> log2_n));
}
