//! A scene by name: a built-in scene or a glTF file, with an optional lat-long
//! environment map replacing its environment, validated.

use super::camera::SceneCamera;
use super::{builtin, Environment, Scene};
use std::path::Path;

/// Loads the named scene (built-in or glTF) and the optional environment map.
pub fn load(name: &str, environment: Option<&Path>, log: &mut dyn FnMut(String)) -> Result<Scene, String> {
    load_with_cameras(name, environment, log).map(|l| l.0)
}

/// [`load`], with the cameras the scene file defines (glTF perspective cameras; none for
/// the built-in scenes).
pub fn load_with_cameras(name: &str, environment: Option<&Path>, log: &mut dyn FnMut(String)) -> Result<(Scene, Vec<SceneCamera>), String> {
    let mut cameras = Vec::new();
    let mut s = match name {
        "cornell" => builtin::cornell(),
        "furnace" => builtin::furnace(1.0, 0.5),
        "slit" => builtin::slit(),
        "sunbeam" => builtin::sunbeam(),
        "room-1m" => builtin::room_1m(),
        "atrium" => builtin::atrium(),
        "museum" => builtin::museum(),
        "dense" => builtin::dense(1 << 20),
        path => {
            let (s, report) = super::import::load(Path::new(path)).map_err(|e| e.to_string())?;
            for n in report.notes {
                log(format!("import: {n}"));
            }
            cameras = report.cameras;
            s
        }
    };
    if let Some(p) = environment {
        let (map, _) = sbf::io::load_map(p, false).map_err(|e| e.to_string())?;
        s.environment = Environment::Map(std::sync::Arc::new(map));
    }
    let degenerate = s.validate().map_err(|e| e.to_string())?;
    if degenerate > 0 {
        log(format!("scene: {degenerate} degenerate triangles skipped"));
    }
    Ok((s, cameras))
}
