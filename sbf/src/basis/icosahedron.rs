//! A regular icosahedron inscribed in the unit sphere: vertices, faces, barycentric
//! normals and face centres. Geometry shared by the lobe layouts (any basis may use
//! icosahedron axes) and the Ambient Dice bases, so it is compiled whatever basis
//! features are enabled.

use glam::DVec3;

/// t = 1/φ = (√5 − 1)/2, the icosahedron's coordinate ratio.
pub const ICOSAHEDRON_T: f64 = 0.618_033_988_749_894_8;

/// cos of the angle between adjacent icosahedron vertices: 1/√5.
pub const ICOSAHEDRON_EDGE_COS: f64 = 0.447_213_595_499_957_9;

/// A regular icosahedron inscribed in the unit sphere: 12 vertices, 20 faces
/// (counter-clockwise seen from outside), with per-face barycentric normals.
#[derive(Debug, Clone)]
pub struct Icosahedron {
    vertices: [DVec3; 12],
    faces: [[usize; 3]; 20],
    /// Per face, n_k ⟂ the other two vertices with n_k·v_k = 1, so that
    /// d = Σ (d·n_k) v_k (gnomonic barycentrics, unnormalised).
    bary_normals: [[DVec3; 3]; 20],
    /// Unit face centres (the spherical triangles are their Voronoi cells).
    centres: [DVec3; 20],
}

impl Icosahedron {
    /// Standard orientation: (±1, ±t, 0), (0, ±1, ±t), (±t, 0, ±1), normalised, in
    /// that order with the sign of the first non-zero coordinate varying fastest.
    pub fn standard() -> Self {
        let t = ICOSAHEDRON_T;
        let raw = [
            DVec3::new(1.0, t, 0.0),
            DVec3::new(-1.0, t, 0.0),
            DVec3::new(1.0, -t, 0.0),
            DVec3::new(-1.0, -t, 0.0),
            DVec3::new(0.0, 1.0, t),
            DVec3::new(0.0, -1.0, t),
            DVec3::new(0.0, 1.0, -t),
            DVec3::new(0.0, -1.0, -t),
            DVec3::new(t, 0.0, 1.0),
            DVec3::new(-t, 0.0, 1.0),
            DVec3::new(t, 0.0, -1.0),
            DVec3::new(-t, 0.0, -1.0),
        ];
        Self::from_vertices(raw.map(|v| v.normalize()))
    }

    /// Orientation of [Roughton19 §8.3.1]: one face centred on +Z and its opposite on
    /// −Z; the first nine vertices (top face, then the two rings) are Roughton's
    /// hemisphere set v₁…v₉ and the last three form the bottom face.
    ///
    /// Rings are at z = ±√((5 + 2√5)/15) and z = ±√((5 − 2√5)/15) (face-centre to
    /// vertex angles of the icosahedron); azimuths are in steps of 120°, rotated
    /// so that v₃ lies on +Y, as in Roughton's table.
    pub fn face_up() -> Self {
        let s5 = 5f64.sqrt();
        let za = ((5.0 + 2.0 * s5) / 15.0).sqrt();
        let zb = ((5.0 - 2.0 * s5) / 15.0).sqrt();
        let at = |z: f64, deg: f64| {
            let r = (1.0 - z * z).sqrt();
            let p = deg.to_radians();
            DVec3::new(r * p.cos(), r * p.sin(), z)
        };
        let v = [
            at(za, -30.0),
            at(za, 210.0),
            at(za, 90.0),
            at(zb, 30.0),
            at(zb, 150.0),
            at(zb, 270.0),
            at(-zb, 210.0),
            at(-zb, 330.0),
            at(-zb, 90.0),
            at(-za, 150.0),
            at(-za, 30.0),
            at(-za, 270.0),
        ];
        Self::from_vertices(v)
    }

    /// Builds faces from adjacency (vertex pairs at the edge angle) and orients them.
    fn from_vertices(vertices: [DVec3; 12]) -> Self {
        let adjacent = |i: usize, j: usize| (vertices[i].dot(vertices[j]) - ICOSAHEDRON_EDGE_COS).abs() < 1e-9;
        let mut faces = [[0usize; 3]; 20];
        let mut n = 0;
        for i in 0..12 {
            for j in (i + 1)..12 {
                for k in (j + 1)..12 {
                    if adjacent(i, j) && adjacent(j, k) && adjacent(i, k) {
                        let (a, b, c) = (vertices[i], vertices[j], vertices[k]);
                        // Counter-clockwise seen from outside: (b − a) × (c − a) points outwards.
                        faces[n] = if (b - a).cross(c - a).dot(a + b + c) > 0.0 { [i, j, k] } else { [i, k, j] };
                        n += 1;
                    }
                }
            }
        }
        assert_eq!(n, 20, "vertices do not form a regular icosahedron");
        let mut bary_normals = [[DVec3::ZERO; 3]; 20];
        let mut centres = [DVec3::ZERO; 20];
        for (f, face) in faces.iter().enumerate() {
            for k in 0..3 {
                let (vk, v1, v2) = (vertices[face[k]], vertices[face[(k + 1) % 3]], vertices[face[(k + 2) % 3]]);
                let c = v1.cross(v2);
                bary_normals[f][k] = c / c.dot(vk);
            }
            centres[f] = (vertices[face[0]] + vertices[face[1]] + vertices[face[2]]).normalize();
        }
        Icosahedron { vertices, faces, bary_normals, centres }
    }

    /// The 12 unit vertices.
    pub fn vertices(&self) -> &[DVec3; 12] {
        &self.vertices
    }
    /// The 20 faces as vertex indices, counter-clockwise from outside.
    pub fn faces(&self) -> &[[usize; 3]; 20] {
        &self.faces
    }
    /// Unit centre of face `f` (the face is the Voronoi cell of its centre).
    pub fn centre(&self, f: usize) -> DVec3 {
        self.centres[f]
    }
    /// Barycentric normals of face `f`.
    pub fn bary_normals(&self, f: usize) -> &[DVec3; 3] {
        &self.bary_normals[f]
    }

    /// Index of the face (spherical triangle) containing unit direction `d`:
    /// the face whose centre is nearest (Voronoi cells of the face centres are
    /// exactly the spherical triangles for a regular polyhedron).
    pub fn face_of(&self, d: DVec3) -> usize {
        let mut best = 0;
        let mut best_dot = f64::NEG_INFINITY;
        for (f, c) in self.centres.iter().enumerate() {
            let s = c.dot(d);
            if s > best_dot {
                best_dot = s;
                best = f;
            }
        }
        best
    }

    /// Face containing `d` and the unnormalised gnomonic barycentrics b_k = d·n_k
    /// (d = Σ b_k v_k; all b_k ≥ 0 up to rounding inside the face).
    pub fn locate(&self, d: DVec3) -> (usize, [f64; 3]) {
        let f = self.face_of(d);
        let n = &self.bary_normals[f];
        (f, [d.dot(n[0]), d.dot(n[1]), d.dot(n[2])])
    }
}
