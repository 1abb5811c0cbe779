//! # probes — Probulator-class comparison of bases and solvers on HDR maps
//!
//! Not implemented yet (issue "probes"). Planned: load Radiance `.hdr`/OpenEXR
//! lat-long maps, compute exact irradiance and GGX references, run every basis and
//! solver, and report error against run time. Until then the README's main job is
//! the `sbf` example `project_sky`, which uses the same built-in procedural sky
//! (`sbf::envmap::ProceduralSky`) that `probes` will default to.
