//! KTX 2.0 files (feature `ktx2`; Khronos, "KTX File Format Specification 2.0"): one mip level, no
//! supercompression, a Khronos data format descriptor from the `ktx2` crate and key/value
//! pairs (`KTXwriter`, and the caller's, e.g. how to decode the texels) — for the textures
//! engines that read KTX2 (Godot, Bevy, three.js) upload as they are: block-compressed
//! lightmaps beside their DDS, and the library's tables.

pub use ktx2::Format;

/// How a KTX2 texture is bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// A 2D texture.
    D2,
    /// A 2D array (`layers` layers).
    D2Array {
        /// Layer count.
        layers: u32,
    },
    /// A 3D texture (`depth` slices).
    D3 {
        /// Depth.
        depth: u32,
    },
}

/// One KTX2 image: its format, size and level data (texels, or blocks row by row then
/// layer or slice by slice, little-endian).
#[derive(Debug, Clone)]
pub struct Ktx2Image<'a> {
    /// Vulkan format of the texels.
    pub format: Format,
    /// Width and height in texels.
    pub size: [u32; 2],
    /// 2D, 2D array or 3D.
    pub dimension: Dimension,
    /// Key/value pairs (keys sorted on writing, as the format requires); `KTXwriter` is
    /// `sbf <version>` unless given.
    pub key_values: Vec<(String, String)>,
    /// The level's bytes.
    pub data: &'a [u8],
}

impl Ktx2Image<'_> {
    /// The file's bytes; an error where the format has no descriptor or the data's length
    /// does not match the size.
    pub fn to_bytes(&self) -> Result<Vec<u8>, String> {
        let (basic, type_size) =
            ktx2::dfd::Basic::from_format(self.format).map_err(|e| format!("{:?}: no data format descriptor: {e:?}", self.format))?;
        // Texel block: dimensions and bytes (from the descriptor: 4 × 4 for BC formats).
        let block = [basic.texel_block_dimensions[0].get() as usize, basic.texel_block_dimensions[1].get() as usize];
        let block_bytes = basic.bytes_planes[0] as usize;
        let dfd_block = ktx2::dfd::Block::Basic(basic).to_vec();
        let (pixel_depth, layer_count, slices) = match self.dimension {
            Dimension::D2 => (0, 0, 1),
            Dimension::D2Array { layers } => (0, layers, layers),
            Dimension::D3 { depth } => (depth, 0, depth),
        };
        let blocks = (self.size[0] as usize).div_ceil(block[0]) * (self.size[1] as usize).div_ceil(block[1]) * slices as usize;
        if self.data.len() != blocks * block_bytes {
            return Err(format!(
                "{:?} {}×{}×{slices}: {} bytes of level data, expected {}",
                self.format,
                self.size[0],
                self.size[1],
                self.data.len(),
                blocks * block_bytes
            ));
        }
        let mut pairs = self.key_values.clone();
        if !pairs.iter().any(|(k, _)| k == "KTXwriter") {
            pairs.push(("KTXwriter".to_string(), format!("sbf {}", env!("CARGO_PKG_VERSION"))));
        }
        pairs.sort();
        // Each entry: its length, "key\0value\0", padded to 4.
        let mut kvd = Vec::new();
        for (k, v) in pairs {
            let mut entry = Vec::new();
            entry.extend(k.as_bytes());
            entry.push(0);
            entry.extend(v.as_bytes());
            entry.push(0);
            kvd.extend((entry.len() as u32).to_le_bytes());
            kvd.extend(entry);
            while kvd.len() % 4 != 0 {
                kvd.push(0);
            }
        }
        let level_index_at = ktx2::Header::LENGTH;
        let dfd_at = level_index_at + ktx2::LevelIndex::LENGTH;
        let dfd_len = 4 + dfd_block.len();
        let kvd_at = dfd_at + dfd_len;
        // Level data aligned to lcm(texel block size, 4).
        let align = lcm(block_bytes.max(1), 4);
        let data_at = (kvd_at + kvd.len()).div_ceil(align) * align;
        let header = ktx2::Header {
            format: Some(self.format),
            type_size,
            pixel_width: self.size[0],
            pixel_height: self.size[1],
            pixel_depth,
            layer_count,
            face_count: 1,
            level_count: 1,
            supercompression_scheme: None,
            index: ktx2::Index {
                dfd_byte_offset: dfd_at as u32,
                dfd_byte_length: dfd_len as u32,
                kvd_byte_offset: kvd_at as u32,
                kvd_byte_length: kvd.len() as u32,
                sgd_byte_offset: 0,
                sgd_byte_length: 0,
            },
        };
        let level = ktx2::LevelIndex {
            byte_offset: data_at as u64,
            byte_length: self.data.len() as u64,
            uncompressed_byte_length: self.data.len() as u64,
        };
        let mut out = Vec::with_capacity(data_at + self.data.len());
        out.extend(header.as_bytes());
        out.extend(level.as_bytes());
        out.extend((dfd_len as u32).to_le_bytes());
        out.extend(dfd_block);
        out.extend(kvd);
        out.resize(data_at, 0);
        out.extend(self.data);
        Ok(out)
    }

    /// Writes the file.
    pub fn write(&self, path: &std::path::Path) -> Result<(), String> {
        std::fs::write(path, self.to_bytes()?).map_err(|e| format!("writing {}: {e}", path.display()))
    }
}

fn lcm(a: usize, b: usize) -> usize {
    let gcd = |mut x: usize, mut y: usize| {
        while y != 0 {
            (x, y) = (y, x % y);
        }
        x
    };
    a / gcd(a, b) * b
}
