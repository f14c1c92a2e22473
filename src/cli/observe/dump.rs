//! `--dump-frame K DIR`: frame `K` for external tools, both meshes as PLY
//! (face `i` is triangle `i`) and the reported, exact and parry pairs as
//! JSON (one character in a room).

use std::path::{Path, PathBuf};

use anyhow::Context;
use cornertree_workbench::io::ply::write_ply;
use cornertree_workbench::truth::Truth;

use super::{Observer, Seen};

/// The frame to dump and where.
pub struct Dump {
    pub frame: usize,
    pub dir: PathBuf,
    /// The scenario's name, written into the JSON.
    pub scenario: String,
}

impl Dump {
    /// Parses `--dump-frame K DIR` against a run of `frames` frames.
    pub fn parse(v: &[String], frames: usize, scenario: &str) -> anyhow::Result<Self> {
        let frame: usize = v[0].parse().map_err(|_| {
            anyhow::anyhow!(
                "--dump-frame: the frame must be a whole number, not {:?}",
                v[0]
            )
        })?;
        if frame >= frames {
            anyhow::bail!(
                "--dump-frame: frame {frame} is past the last frame ({})",
                frames - 1
            );
        }
        Ok(Self {
            frame,
            dir: PathBuf::from(&v[1]),
            scenario: scenario.to_string(),
        })
    }

    /// The files written (for the run's summary).
    pub fn files(&self) -> String {
        format!(
            "frame {}: {dir}/avatar.ply, {dir}/environment.ply, {dir}/pairs.json\n",
            self.frame,
            dir = self.dir.display()
        )
    }

    fn write(&self, seen: &Seen<'_>) -> anyhow::Result<()> {
        let session = seen.session;
        let dir = &self.dir;
        std::fs::create_dir_all(dir)?;
        let character = &session.scene.first().character;
        let positions = &session.buffers[0].positions;
        let env = &session.scene.environment.mesh;
        write_ply(&dir.join("avatar.ply"), positions, character.mesh.indices())?;
        write_ply(&dir.join("environment.ply"), env.positions(), env.indices())?;
        // The truth of this frame (computed here when the run skips it).
        let own;
        let truth = match seen.reference {
            Some(r) => &r.truth,
            None => {
                let mut t = Truth::new(&session.scene)?;
                t.update(&session.scene, &session.buffers, &session.object_poses)?;
                own = t;
                &own
            }
        };
        let room = truth.room(0);
        let pairs_of = |m: usize| {
            session
                .contacts(m)
                .room_pairs
                .iter()
                .map(|p| [p.triangle, p.room_triangle])
                .collect::<Vec<_>>()
        };
        let as_arrays = |v: &[(u32, u32)]| v.iter().map(|&(a, b)| [a, b]).collect::<Vec<_>>();
        let by_method: serde_json::Map<String, serde_json::Value> = session
            .methods()
            .enumerate()
            .map(|(m, method)| (method.name().to_string(), serde_json::json!(pairs_of(m))))
            .collect();
        let first = session.methods().next();
        let json = serde_json::json!({
            "scenario": self.scenario,
            "frame": seen.k,
            "method": first.map(|m| m.name()),
            "reported": first.map(|_| pairs_of(0)).unwrap_or_default(),
            "reference": as_arrays(&room.exact),
            "parry": as_arrays(&room.parry),
            "reported_by_method": by_method,
        });
        std::fs::write(dir.join("pairs.json"), serde_json::to_string_pretty(&json)?)?;
        Ok(())
    }
}

impl Observer for Dump {
    fn needs_skin(&self, k: usize) -> bool {
        k == self.frame
    }

    fn frame_end(&mut self, seen: &Seen<'_>) -> anyhow::Result<()> {
        if seen.k != self.frame {
            return Ok(());
        }
        self.write(seen).with_context(|| {
            format!(
                "{}: cannot dump frame {}",
                Path::new(&self.dir).display(),
                seen.k
            )
        })
    }
}
