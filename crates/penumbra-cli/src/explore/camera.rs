//! Moving the scene's camera: orbiting the eye around the point it looks
//! at, and dollying it along the view. The camera is the description's
//! (`position`, `look_at`, `up` of the sensor, as a scene file or Mitsuba's
//! `to_world` gives them), so a moved camera is only a changed description:
//! the world is reused when the scene is built again.

use penumbra::description::{KeyPath, Kind, Located, Node, Origin, Value};
use penumbra::math::Vec3;

/// Closest the view may come to `up` when orbiting, in radians.
const POLE: f32 = 0.01;

/// Dolly factors allowed in one request.
pub const DOLLY_RANGE: (f32, f32) = (0.01, 100.0);

/// The camera's eye and target, at the shutter's open and close.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    /// `position_end` and `look_at_end`, when the camera moves.
    pub end: Option<(Vec3, Vec3)>,
}

impl Placement {
    /// The placement the description's sensor gives (the camera's defaults
    /// where it gives none); `None` without a sensor.
    pub fn of(root: &Node) -> Option<Placement> {
        let sensor = root.child(Kind::Sensor)?;
        let vec = |key: &str, default: Vec3| read_vec3(sensor, key).unwrap_or(default);
        let position = vec("position", Vec3::new(0.0, 1.0, 5.0));
        let look_at = vec("look_at", Vec3::ZERO);
        let end = match (
            read_vec3(sensor, "position_end"),
            read_vec3(sensor, "look_at_end"),
        ) {
            (None, None) => None,
            (p, l) => Some((p.unwrap_or(position), l.unwrap_or(look_at))),
        };
        Some(Placement {
            position,
            look_at,
            up: vec("up", Vec3::Y),
            end,
        })
    }

    /// Turns the eye around the target: `yaw` degrees about `up`, then
    /// `pitch` degrees towards it (stopping short of it).
    pub fn orbit(&mut self, yaw: f32, pitch: f32) {
        let up = self.up.normalize_or(Vec3::Y);
        let turn = |eye: Vec3, at: Vec3| at + orbit_offset(eye - at, up, yaw, pitch);
        self.position = turn(self.position, self.look_at);
        if let Some((p, l)) = &mut self.end {
            *p = turn(*p, *l);
        }
    }

    /// Moves the eye along the view: its distance to the target times
    /// `factor` (below 1: closer).
    pub fn dolly(&mut self, factor: f32) {
        let scale = |eye: Vec3, at: Vec3| at + (eye - at) * factor;
        self.position = scale(self.position, self.look_at);
        if let Some((p, l)) = &mut self.end {
            *p = scale(*p, *l);
        }
    }

    /// Writes the placement into the description's sensor.
    pub fn apply(&self, root: &mut Node) {
        let Some(sensor) = root.child_mut(Kind::Sensor) else {
            return;
        };
        let mut set = |key: &str, v: Vec3| {
            let origin = Origin::unlocated(KeyPath::root().key("camera").key(key));
            let items = v
                .to_array()
                .iter()
                .map(|&x| Located::new(Value::Float(f64::from(x)), origin.clone()))
                .collect();
            sensor.set_prop(key, Located::new(Value::Array(items), origin));
        };
        set("position", self.position);
        set("look_at", self.look_at);
        if let Some((p, l)) = self.end {
            set("position_end", p);
            set("look_at_end", l);
        }
    }
}

/// `offset` (eye minus target) turned `yaw` degrees about `up` and
/// `pitch` degrees towards `up`, its length kept.
fn orbit_offset(offset: Vec3, up: Vec3, yaw: f32, pitch: f32) -> Vec3 {
    let r = offset.length();
    if r <= 0.0 {
        return offset;
    }
    let along = offset.dot(up);
    let across = offset - along * up;
    let side = if across.length() > 1e-6 * r {
        across.normalize()
    } else {
        up.any_orthonormal_vector()
    };
    // The azimuth turns `side` about `up`; the polar angle is measured from `up`.
    let (s, c) = (-yaw).to_radians().sin_cos();
    let side = side * c + up.cross(side) * s;
    let theta = (along / r).clamp(-1.0, 1.0).acos();
    let theta = (theta - pitch.to_radians()).clamp(POLE, std::f32::consts::PI - POLE);
    r * (theta.cos() * up + theta.sin() * side)
}

/// A property of three numbers, if the node has one.
fn read_vec3(node: &Node, key: &str) -> Option<Vec3> {
    let Value::Array(items) = &node.prop(key)?.value.value else {
        return None;
    };
    let numbers: Vec<f32> = items
        .iter()
        .filter_map(|v| match v.value {
            Value::Float(x) => Some(x as f32),
            Value::Int(n) => Some(n as f32),
            _ => None,
        })
        .collect();
    match numbers[..] {
        [x, y, z] => Some(Vec3::new(x, y, z)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn explore_orbit_keeps_the_distance_and_turns_about_up() {
        let mut p = Placement {
            position: Vec3::new(0.0, 0.0, 5.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            end: None,
        };
        p.orbit(90.0, 0.0);
        assert!(
            near(p.position, Vec3::new(-5.0, 0.0, 0.0))
                || near(p.position, Vec3::new(5.0, 0.0, 0.0))
        );
        assert!((p.position.length() - 5.0).abs() < 1e-5);
        p.orbit(0.0, 45.0);
        assert!((p.position.y - 5.0 * (45f32).to_radians().sin()).abs() < 1e-4);
        // Never over the pole.
        p.orbit(0.0, 400.0);
        assert!(p.position.y < 5.0 && p.position.normalize().dot(Vec3::Y) < 1.0);
        p.dolly(0.5);
        assert!((p.position.length() - 2.5).abs() < 1e-4);
    }

    #[test]
    fn explore_placement_reads_and_writes_the_sensor() {
        let text = "[camera]\nposition = [1, 2, 3]\nlook_at = [0.0, 1.0, 0.0]\n";
        let here = std::path::Path::new(".");
        let src =
            penumbra::scene::SceneSource::from_toml(text, here, here, &Default::default()).unwrap();
        let mut root = src.root.clone();
        let mut p = Placement::of(&root).unwrap();
        assert_eq!(p.position, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(p.look_at, Vec3::Y);
        p.dolly(2.0);
        p.apply(&mut root);
        assert!(near(
            Placement::of(&root).unwrap().position,
            Vec3::new(2.0, 3.0, 6.0)
        ));
    }
}
