//! A scene by name: a built-in scene or a glTF file, with an optional lat-long
//! environment map replacing its environment, validated.

use super::camera::SceneCamera;
use super::{builtin, Environment, Scene};
use std::path::Path;

/// The built-in scenes' names, in [`SCENE_HELP`]'s order ([`load`] knows each).
pub const BUILTIN: [&str; 8] = ["cornell", "furnace", "slit", "sunbeam", "room-1m", "atrium", "museum", "dense"];

/// What `--scene` accepts, for every command that takes one (`baker`, `render`, `slc`).
pub const SCENE_HELP: &str = "Scene: a .gltf/.glb file, or a built-in one: `cornell` (the default Cornell-style \
    box), `furnace` (a closed test box), `slit` (a room lit through a slit), `sunbeam` (the slit room lit by a sun \
    through the slit: a small bright indirect region), `room-1m` (1 M lightmapped triangles, the fair benchmark), \
    `atrium` (a 0.29 M-triangle hall with columns, arches and banners, lit by a sun and the sky through a skylight: \
    the renderer's Table 8.1 workload), `museum` (a glossy hall lit by three spot lights: the light-culling \
    workload), `dense` (cornell + a 1 M-triangle sphere).";

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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every built-in name loads and is in the help text; an unknown name is read as a file
    /// and refused with its path. (The list, the help and `load`'s match cannot drift apart.)
    #[test]
    fn every_builtin_name_loads_and_is_documented() {
        for name in BUILTIN {
            assert!(SCENE_HELP.contains(&format!("`{name}`")), "{name} is missing from SCENE_HELP");
            let s = load(name, None, &mut |_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(!s.meshes.is_empty(), "{name}: no meshes");
        }
        let e = load("no-such-scene", None, &mut |_| {}).unwrap_err();
        assert!(e.contains("no-such-scene"), "{e}");
    }
}
