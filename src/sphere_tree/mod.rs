//! Sphere trees (paper §3). STUB.
