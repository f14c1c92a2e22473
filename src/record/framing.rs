//! Blueprints whose 3D views open framed on what they show: a view's eye
//! (position and look target) set from the first frame's bodies.
//!
//! rerun 0.36's blueprint builder has no public way to set a view's
//! properties (the `EyeControls3D` archetype exists, but `View::add_property`
//! is crate-private). So [`send`] captures what the builder would send (the
//! blueprint sent to an in-memory stream), logs each eye into the same
//! blueprint store at `view/<id>/EyeControls3D` (the path the builder uses
//! for view properties, e.g. a map view's background), and sends the whole
//! to the recording with the builder's activation command. The eye is
//! logged on the `blueprint` timeline at 0, as the builder logs the rest, so
//! the viewer's own camera moves override it (static data would lock it).

use nalgebra::Point3;
use rerun::blueprint::{Blueprint, BlueprintActivation, ContainerLike};
use rerun::external::re_log_types::{BlueprintActivationCommand, LogMsg};
use rerun::external::re_sdk_types::blueprint::archetypes::EyeControls3D;
use rerun::{EntityPath, RecordingStream, RecordingStreamBuilder};

use crate::scenario::Resolved;

/// Where a 3D view's eye starts.
#[derive(Clone, Debug)]
pub struct Eye {
    /// The view's blueprint path (`view/<id>`).
    pub view: EntityPath,
    pub position: [f32; 3],
    pub look_target: [f32; 3],
}

/// A blueprint and the eyes of some of its 3D views.
pub struct FramedBlueprint {
    pub blueprint: Blueprint,
    pub eyes: Vec<Eye>,
}

impl From<Blueprint> for FramedBlueprint {
    fn from(blueprint: Blueprint) -> Self {
        Self {
            blueprint,
            eyes: Vec::new(),
        }
    }
}

/// The blueprint path of `view` (a view made by the builder).
pub fn view_path(view: &ContainerLike) -> Option<EntityPath> {
    match view {
        ContainerLike::View(v) => Some(v.blueprint_path()),
        _ => None,
    }
}

/// An axis-aligned box in world coordinates (Y up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Point3<f32>,
    pub max: Point3<f32>,
}

impl Bounds {
    /// The eye of a view of this box: looking at its centre from the front
    /// right and above (direction (1, 0.6, 1)), far enough for the box's
    /// diagonal to fit a view's height with room around it.
    pub fn eye(&self, view: EntityPath) -> Eye {
        let centre = nalgebra::center(&self.min, &self.max);
        let diagonal = (self.max - self.min).norm().max(0.5);
        let direction = nalgebra::Vector3::new(1.0f32, 0.6, 1.0).normalize();
        let position = centre + direction * (1.1 * diagonal);
        Eye {
            view,
            position: [position.x, position.y, position.z],
            look_target: [centre.x, centre.y, centre.z],
        }
    }
}

/// The box around every body at frame 0: the characters posed and skinned
/// as the run will pose them, the moving objects where their motion puts
/// them; `None` without bodies.
pub fn first_frame_bounds(scene: &Resolved) -> Option<Bounds> {
    let mut bounds: Option<Bounds> = None;
    let mut add = |p: &Point3<f32>| {
        let b = bounds.get_or_insert(Bounds { min: *p, max: *p });
        b.min = b.min.inf(p);
        b.max = b.max.sup(p);
    };
    for actor in &scene.characters {
        let mut buffers = cornertree::character::PoseBuffers::new(&actor.character);
        actor.pose_and_skin_frame(&mut buffers, 0);
        buffers.positions.iter().for_each(&mut add);
    }
    let t = scene.world_time(0);
    for object in &scene.objects {
        let pose = object.motion.pose_at(t);
        for p in object.mesh.positions() {
            add(&(pose * p));
        }
    }
    bounds
}

/// Sends `framed` to `stream`, active and default, with its eyes.
pub fn send(stream: &RecordingStream, framed: &FramedBlueprint) -> anyhow::Result<()> {
    let app = stream
        .store_info()
        .map(|info| info.application_id().clone())
        .unwrap_or_else(|| "cornertree".into());
    let (memory, storage) = RecordingStreamBuilder::new(app.clone()).memory()?;
    framed.blueprint.send(
        &memory,
        BlueprintActivation {
            make_active: true,
            make_default: true,
        },
    )?;
    memory.flush_blocking()?;
    let mut activation: Option<BlueprintActivationCommand> = None;
    let mut messages: Vec<LogMsg> = Vec::new();
    for message in storage.take() {
        match message {
            LogMsg::BlueprintActivationCommand(command) => activation = Some(command),
            other => messages.push(other),
        }
    }
    let activation =
        activation.ok_or_else(|| anyhow::anyhow!("the blueprint builder sent no activation"))?;
    let blueprint_id = activation.blueprint_id.clone();
    // The memory stream's own store info is not the blueprint's.
    messages.retain(|m| m.store_id() == &blueprint_id);
    if !framed.eyes.is_empty() {
        let (eyes, eye_storage) = RecordingStreamBuilder::new(app)
            .recording_id(blueprint_id.recording_id().clone())
            .blueprint()
            .memory()?;
        eyes.set_time_sequence("blueprint", 0);
        for eye in &framed.eyes {
            eyes.log(
                format!("{}/EyeControls3D", eye.view),
                &EyeControls3D::new()
                    .with_position(eye.position)
                    .with_look_target(eye.look_target),
            )?;
        }
        eyes.flush_blocking()?;
        messages.extend(
            eye_storage
                .take()
                .into_iter()
                .filter(|m| matches!(m, LogMsg::ArrowMsg(id, _) if id == &blueprint_id)),
        );
    }
    stream.send_blueprint(messages, activation);
    Ok(())
}
