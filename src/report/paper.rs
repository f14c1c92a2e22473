//! Figures published in the paper, printed *beside* our measurements and
//! always labelled as the paper's. Nothing here feeds a computation.

/// Table 1: spheres on levels 1–7 of a corner-tree and of a quaternary tree.
pub const TABLE1_CORNER_TREE: [usize; 7] = [1, 4, 12, 36, 84, 180, 372];
pub const TABLE1_QUATERNARY: [usize; 7] = [1, 4, 16, 64, 256, 1024, 4096];

/// §6: vertices of the paper's avatar and rooms.
pub const AVATAR_VERTICES: usize = 44_345;
pub const MUSEUM_VERTICES: usize = 9_482;
pub const LIVING_ROOM_VERTICES: usize = 133_139;

/// One column of Tables 2–3 as the paper prints it (approximate figures,
/// "≈"); `None` where the paper leaves the cell empty.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PaperColumn {
    pub sphere_sphere: u64,
    pub tri_tri: Option<u64>,
    pub plane_sphere: Option<u64>,
    pub operations: u64,
}

/// Table 2 (museum): original, sphere division, plane-sphere.
pub const TABLE2_MUSEUM: [(&str, PaperColumn); 3] = [
    (
        "original",
        PaperColumn {
            sphere_sphere: 200_000,
            tri_tri: Some(150_000),
            plane_sphere: None,
            operations: 17_000_000,
        },
    ),
    (
        "sphere-division",
        PaperColumn {
            sphere_sphere: 15_000,
            tri_tri: Some(150),
            plane_sphere: None,
            operations: 165_000,
        },
    ),
    (
        "plane-sphere",
        PaperColumn {
            sphere_sphere: 5_000,
            tri_tri: None,
            plane_sphere: Some(2_000),
            operations: 110_000,
        },
    ),
];

/// Table 3 (living room): original, sphere division, plane-sphere.
pub const TABLE3_LIVING_ROOM: [(&str, PaperColumn); 3] = [
    (
        "original",
        PaperColumn {
            sphere_sphere: 80_000,
            tri_tri: Some(70_000),
            plane_sphere: None,
            operations: 7_000_000,
        },
    ),
    (
        "sphere-division",
        PaperColumn {
            sphere_sphere: 80_000,
            tri_tri: Some(50_000),
            plane_sphere: None,
            operations: 5_000_000,
        },
    ),
    (
        "plane-sphere",
        PaperColumn {
            sphere_sphere: 8_000,
            tri_tri: None,
            plane_sphere: Some(275),
            operations: 90_000,
        },
    ),
];
