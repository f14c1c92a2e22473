//! Figures published in the paper, printed *beside* our measurements and
//! always labelled as the paper's. Nothing here feeds a computation.

/// Table 1: spheres on levels 1–7 of a corner-tree and of a quaternary tree.
pub const TABLE1_CORNER_TREE: [usize; 7] = [1, 4, 12, 36, 84, 180, 372];
pub const TABLE1_QUATERNARY: [usize; 7] = [1, 4, 16, 64, 256, 1024, 4096];

/// §6: vertices of the paper's avatar and rooms.
pub const AVATAR_VERTICES: usize = 44_345;
pub const MUSEUM_VERTICES: usize = 9_482;
pub const LIVING_ROOM_VERTICES: usize = 133_139;
