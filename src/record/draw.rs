//! Small drawing helpers the recorders and figures share: points, meshes,
//! triangle soups, spheres grouped by level, body entity names and colours.

use cornertree::geometry::{Point, Sphere};
use cornertree::world::PairKind;

use super::layout::{self, Rgba};

/// A point as Rerun takes it.
pub fn p3(p: &Point) -> [f32; 3] {
    [p.x, p.y, p.z]
}

/// A body's entity name: its index (so entities sort as the scenario lists
/// them) and its name with anything but letters, digits, `-` and `_` made `_`.
pub fn body_entity(index: usize, name: &str) -> String {
    let clean: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{index:02}_{clean}")
}

/// Colour of the colliding triangles of a pair kind (both sides).
pub fn kind_color(kind: PairKind) -> Rgba {
    match kind {
        PairKind::Environment => layout::HIT_ENV_COLOR,
        PairKind::Objects => layout::HIT_OBJECT_COLOR,
        PairKind::Characters => layout::HIT_CHARACTER_COLOR,
        PairKind::SelfContact => layout::HIT_SELF_COLOR,
    }
}

/// Spheres grouped per level (`keep` filters by node index).
pub fn spheres_by_level(
    spheres: impl Iterator<Item = Sphere>,
    level_of: &[u8],
    levels: usize,
    keep: impl Fn(usize) -> bool,
) -> Vec<(Vec<[f32; 3]>, Vec<f32>)> {
    let mut out = vec![(Vec::new(), Vec::new()); levels];
    for (i, s) in spheres.enumerate() {
        if keep(i) {
            let l = level_of[i] as usize;
            out[l].0.push(p3(&s.center));
            out[l].1.push(s.radius);
        }
    }
    out
}

/// Spheres as points with scene-unit radii (fast for tens of thousands).
pub fn points(centers: Vec<[f32; 3]>, radii: Vec<f32>, color: Rgba) -> rerun::Points3D {
    rerun::Points3D::new(centers)
        .with_radii(radii)
        .with_colors([color])
}

/// Spheres as wireframe ellipsoids (for a few hundred at most).
pub fn wireframes(centers: Vec<[f32; 3]>, radii: Vec<f32>, color: Rgba) -> rerun::Ellipsoids3D {
    rerun::Ellipsoids3D::from_centers_and_radii(centers, radii)
        .with_colors([color])
        .with_fill_mode(rerun::FillMode::MajorWireframe)
        .with_line_radii([rerun::Radius::new_ui_points(0.5)])
}

/// An indexed mesh with one colour.
pub fn mesh3d(positions: &[Point], indices: &[[u32; 3]], color: Rgba) -> rerun::Mesh3D {
    rerun::Mesh3D::new(positions.iter().map(p3))
        .with_triangle_indices(indices.iter().copied())
        .with_albedo_factor(color)
}

/// The triangles `which` of a mesh, as a small unindexed mesh.
pub fn soup(
    positions: &[Point],
    indices: &[[u32; 3]],
    which: &[u32],
    color: Rgba,
) -> rerun::Mesh3D {
    let verts = which
        .iter()
        .flat_map(|&t| indices[t as usize].map(|v| p3(&positions[v as usize])));
    let tris = (0..which.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]);
    rerun::Mesh3D::new(verts)
        .with_triangle_indices(tris)
        .with_albedo_factor(color)
}

/// The level count of a tree whose node levels are `levels`.
pub fn level_count(levels: &[u8]) -> usize {
    levels.iter().map(|&l| l as usize + 1).max().unwrap_or(0)
}
