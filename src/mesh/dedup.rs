//! Edge de-duplication. STUB.
use super::TriMesh;
pub struct EdgeDedup { pub kept: Vec<bool> }
pub fn dedup_edges(_m: &TriMesh) -> EdgeDedup { unimplemented!() }
