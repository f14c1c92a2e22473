//! Reads `.rrd` recordings back (rerun's `rrd` decoder), for tests.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use rerun::external::re_log_encoding::DecoderApp;
use rerun::log::{Chunk, LogMsg};
use rerun::{ComponentIdentifier, StoreKind};

/// The recording store's chunks of a file.
pub struct Rrd {
    pub chunks: Vec<Chunk>,
    /// Whether a blueprint store came with it.
    pub has_blueprint: bool,
    /// The blueprint store's chunks.
    pub blueprint: Vec<Chunk>,
    /// The first decoding error (a truncated file ends with one).
    pub error: Option<String>,
}

/// Reads what `path` holds when called: a recording still being written
/// grows faster than an unoptimised decoder reads, so it is read up to its
/// length at the start, not to an end that keeps moving.
pub fn read_rrd(path: &Path) -> Rrd {
    use std::io::Read;
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let len = file.metadata().map(|m| m.len()).unwrap_or(u64::MAX);
    let file = file.take(len);
    let mut rrd = Rrd {
        chunks: Vec::new(),
        has_blueprint: false,
        blueprint: Vec::new(),
        error: None,
    };
    for msg in DecoderApp::decode_lazy(std::io::BufReader::new(file)) {
        match msg {
            Ok(LogMsg::ArrowMsg(store, m)) => {
                if store.kind() == StoreKind::Recording {
                    rrd.chunks.push(Chunk::from_arrow_msg(&m).expect("a chunk"));
                } else {
                    rrd.has_blueprint = true;
                    rrd.blueprint
                        .push(Chunk::from_arrow_msg(&m).expect("a blueprint chunk"));
                }
            }
            Ok(_) => {}
            Err(e) => {
                rrd.error = Some(e.to_string());
                break;
            }
        }
    }
    rrd
}

fn path_of(c: &Chunk) -> String {
    c.entity_path()
        .to_string()
        .trim_start_matches('/')
        .to_string()
}

impl Rrd {
    pub fn entity_paths(&self) -> BTreeSet<String> {
        self.chunks.iter().map(path_of).collect()
    }

    /// `(frame, instance count)` of every row of `component` on `entity`;
    /// static rows have frame `None`.
    pub fn rows(&self, entity: &str, component: ComponentIdentifier) -> Vec<(Option<i64>, usize)> {
        self.rows_on("frame", entity, component)
    }

    /// As [`Self::rows`] on another timeline.
    pub fn rows_on(
        &self,
        timeline: &str,
        entity: &str,
        component: ComponentIdentifier,
    ) -> Vec<(Option<i64>, usize)> {
        let mut out = Vec::new();
        for c in self.chunks.iter().filter(|c| path_of(c) == entity) {
            let lens = c.iter_component_offsets(component).map(|s| s.len);
            let times = c
                .iter_component_indices(
                    rerun::TimelineName::try_new(timeline).expect("a timeline name"),
                    component,
                )
                .map(|(t, _)| (!c.is_static()).then(|| t.as_i64()));
            out.extend(times.zip(lens));
        }
        out.sort();
        out
    }

    /// Instance count per frame (static rows left out).
    pub fn counts_per_frame(
        &self,
        entity: &str,
        component: ComponentIdentifier,
    ) -> BTreeMap<i64, usize> {
        self.rows(entity, component)
            .into_iter()
            .filter_map(|(t, n)| t.map(|t| (t, n)))
            .collect()
    }

    /// Frames at which `entity` has any data.
    pub fn frames(&self, entity: &str) -> BTreeSet<i64> {
        let mut out = BTreeSet::new();
        for c in self.chunks.iter().filter(|c| path_of(c) == entity) {
            if let Some(col) = c.timelines().get(&"frame".into()) {
                out.extend(col.times().map(|t| t.as_i64()));
            }
        }
        out
    }

    /// Every 3D view eye the blueprint sets: `(entity, position, look target)`.
    pub fn eyes(&self) -> Vec<(String, [f32; 3], [f32; 3])> {
        use rerun::external::re_sdk_types::blueprint::archetypes::EyeControls3D;
        let pid = EyeControls3D::descriptor_position().component;
        let tid = EyeControls3D::descriptor_look_target().component;
        let mut out = Vec::new();
        for c in self
            .blueprint
            .iter()
            .filter(|c| path_of(c).ends_with("/EyeControls3D"))
        {
            let positions = c.iter_component::<rerun::components::Position3D>(pid);
            let targets = c.iter_component::<rerun::components::Position3D>(tid);
            for (p, t) in positions.zip(targets) {
                out.push((path_of(c), p[0].0.0, t[0].0.0));
            }
        }
        out
    }

    /// The vertex positions of a `Mesh3D` entity at `frame`.
    pub fn mesh_vertices(&self, entity: &str, frame: i64) -> Vec<[f32; 3]> {
        let id = rerun::Mesh3D::descriptor_vertex_positions().component;
        let mut out = Vec::new();
        for c in self.chunks.iter().filter(|c| path_of(c) == entity) {
            let times = c
                .iter_component_indices("frame".into(), id)
                .map(|(t, _)| t.as_i64());
            let values = c.iter_component::<rerun::components::Position3D>(id);
            for (t, v) in times.zip(values) {
                if t == frame {
                    out.extend(v.iter().map(|p| p.0.0));
                }
            }
        }
        out
    }

    /// The scalar logged on `entity` at each frame.
    pub fn scalars(&self, entity: &str) -> BTreeMap<i64, f64> {
        let id = rerun::Scalars::descriptor_scalars().component;
        let mut out = BTreeMap::new();
        for c in self.chunks.iter().filter(|c| path_of(c) == entity) {
            let times = c
                .iter_component_indices("frame".into(), id)
                .map(|(t, _)| t.as_i64());
            let values = c.iter_component::<rerun::components::Scalar>(id);
            for (t, v) in times.zip(values) {
                out.insert(t, v[0].0.0);
            }
        }
        out
    }
}

/// A sphere as logged: centre and radius, as bit patterns (exact, sortable).
pub type LoggedSphere = ([u32; 3], u32);

fn bits(c: [f32; 3], r: f32) -> LoggedSphere {
    (c.map(f32::to_bits), r.to_bits())
}

impl Rrd {
    /// The spheres of an `Ellipsoids3D` entity at each frame (centres and the
    /// first half-size), sorted.
    pub fn ellipsoids(&self, entity: &str) -> BTreeMap<i64, Vec<LoggedSphere>> {
        let cid = rerun::Ellipsoids3D::descriptor_centers().component;
        let hid = rerun::Ellipsoids3D::descriptor_half_sizes().component;
        let mut out: BTreeMap<i64, Vec<LoggedSphere>> = BTreeMap::new();
        for c in self.chunks.iter().filter(|c| path_of(c) == entity) {
            let times = c
                .iter_component_indices("frame".into(), cid)
                .map(|(t, _)| t.as_i64());
            let centers = c.iter_component::<rerun::components::Translation3D>(cid);
            let halves = c.iter_component::<rerun::components::HalfSize3D>(hid);
            for ((t, cs), hs) in times.zip(centers).zip(halves) {
                assert_eq!(cs.len(), hs.len(), "{entity} frame {t}");
                let v = out.entry(t).or_default();
                v.extend(cs.iter().zip(hs.iter()).map(|(c, h)| bits(c.0.0, h.0.0[0])));
                v.sort_unstable();
            }
        }
        out
    }

    /// The points (centres and radii) of a `Points3D` entity at each frame,
    /// sorted.
    pub fn points(&self, entity: &str) -> BTreeMap<i64, Vec<LoggedSphere>> {
        let pid = rerun::Points3D::descriptor_positions().component;
        let rid = rerun::Points3D::descriptor_radii().component;
        let mut out: BTreeMap<i64, Vec<LoggedSphere>> = BTreeMap::new();
        for c in self.chunks.iter().filter(|c| path_of(c) == entity) {
            let times = c
                .iter_component_indices("frame".into(), pid)
                .map(|(t, _)| t.as_i64());
            let centers = c.iter_component::<rerun::components::Position3D>(pid);
            let radii = c.iter_component::<rerun::components::Radius>(rid);
            for ((t, ps), rs) in times.zip(centers).zip(radii) {
                assert_eq!(ps.len(), rs.len(), "{entity} frame {t}");
                let v = out.entry(t).or_default();
                v.extend(ps.iter().zip(rs.iter()).map(|(p, r)| bits(p.0.0, r.0.0)));
                v.sort_unstable();
            }
        }
        out
    }
}
