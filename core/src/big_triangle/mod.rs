//! Hierarchies inside big triangles (paper §4–5).
//!
//! A triangle of the environment is *big* when its longest edge exceeds a
//! threshold. Its single leaf sphere would swallow the whole character, so a
//! hierarchy of sub-triangle spheres is built inside it:
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`subtriangle`] | [`SubTriangle`]: the four-way midpoint split, boundary edges tracked | §5, Fig. 2 |
//! | [`hierarchy`] | [`Division`] (sphere division, quaternary, corner-tree) as a sphere tree | §5, Fig. 3, Table 1 |
//!
//! Leaves point back to the original triangle: sphere division answers them
//! with the triangle-triangle test against it, corner-trees with the
//! plane-sphere test against its plane.

pub mod hierarchy;
pub mod subtriangle;

pub use hierarchy::{Division, DivisionKind};
pub use subtriangle::SubTriangle;
