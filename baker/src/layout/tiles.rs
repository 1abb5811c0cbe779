//! The tile format of texel indices ([Roughton19 §5.2, eqs. 5.2–5.3]): an atlas cut into
//! square tiles of 2^log2_n texels a side, row by row within a tile, so consecutive items
//! are a compact block of texels. The WGSL twin is `gpu/prims/tile.wgsl`.

/// Tile-format index of texel (x, y) ([Roughton19 eq. 5.2]): tiles of 2^log2_n texels a side,
/// `tiles_per_row` = ⌈width / n⌉.
pub fn tile_index(x: u32, y: u32, log2_n: u32, tiles_per_row: u32) -> u32 {
    let n = 1u32 << log2_n;
    let tile = (x >> log2_n) + tiles_per_row * (y >> log2_n);
    (tile << (2 * log2_n)) | ((x & (n - 1)) + n * (y & (n - 1)))
}

/// The texel of a tile-format index (the inverse of [`tile_index`]; eq. 5.3 for the
/// tile's origin).
pub fn tile_coords(i: u32, log2_n: u32, tiles_per_row: u32) -> (u32, u32) {
    let n = 1u32 << log2_n;
    let tile = i >> (2 * log2_n);
    let within = i & (n * n - 1);
    (n * (tile % tiles_per_row) + (within & (n - 1)), n * (tile / tiles_per_row) + (within >> log2_n))
}

/// The side of the texel tiles a bake's lightmap items follow (2³).
pub const ITEM_TILE: u32 = 8;

/// The valid texels of a `width`-wide atlas of `len` texels in a bake's item order
/// ([Roughton19 §5.2, eq. 5.2]): 8 × 8 texel tiles, row by row within a tile, so that
/// consecutive GPU threads bake a compact block of texels (nearby origins, similar
/// normals) rather than a strip of one row.
pub fn item_order(width: usize, len: usize, valid: impl Fn(usize) -> bool) -> Vec<usize> {
    let tiles_per_row = width.div_ceil(ITEM_TILE as usize) as u32;
    let mut order: Vec<usize> = (0..len).filter(|k| valid(*k)).collect();
    order.sort_by_key(|k| tile_index((k % width) as u32, (k / width) as u32, ITEM_TILE.trailing_zeros(), tiles_per_row));
    order
}
