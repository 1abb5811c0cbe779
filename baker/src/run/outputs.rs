//! A finished bake to files: validity and filter accounts, denoising and seam stitching
//! (the post layer) before dilation, the images, the preview, the runtime shader library,
//! bake.json and probes.json.

use super::runtime::write_runtime;
use super::Options;
use crate::accumulate::{BakeState, Solver, Targets};
use crate::layout::lightmap::Lightmap;
use crate::output;
use crate::output::bake_json::{
    AdaptiveJson, BakeJson, BasisJson, DenoiseJson, FileJson, FilterJson, GuidingJson, IrradianceRatioJson, LayoutJson, ProbeJson,
    ProbesJson, ProbesSummaryJson, ProfileJson, SeamsJson, StageSecondsJson, ValidityJson,
};
use crate::post::images::LightmapImages;
use crate::post::refit::IrradianceRatio;
use crate::scene::bvh::Bvh;
use crate::scene::Scene;
use sbf::glam::Vec3;
use std::time::Instant;

/// Wall time of the bake's stages, for bake.json.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StageTimes {
    pub(crate) lightmap_passes: f64,
    pub(crate) probe_passes: Option<f64>,
}

/// What the outputs record besides the states.
pub(crate) struct OutputContext<'a> {
    pub(crate) probe_positions: &'a [Vec3],
    pub(crate) relocated: &'a [(usize, Vec3)],
    pub(crate) device: &'a str,
    /// The GPU pipeline that ran the passes, or that the CPU path ran them.
    pub(crate) pipeline: &'static str,
    pub(crate) glossy: bool,
    pub(crate) t0: Instant,
    pub(crate) times: StageTimes,
}

/// bake.json's account of ray guiding (null when off).
fn guiding_json(o: &Options, targets: &Targets, state: &BakeState) -> Option<GuidingJson> {
    let g = o.spec.config.guiding?;
    let bins = crate::sampling::guiding::BIN_COUNT;
    let learned = state.guide_sums.chunks(bins).filter(|c| c.iter().any(|v| *v > 0.0)).count();
    let mut rebuilds = Vec::new();
    let mut p = g.learn_passes;
    while p < state.passes && p > 0 {
        rebuilds.push(p);
        p *= 2;
    }
    Some(GuidingJson {
        method: "first-bounce ray guiding ([HWRTL]): 8x8-texel clusters split by chart and normal, 16x16 equal-area concentric bins, quadtree relaxation, mixture with the uniform hemisphere",
        clusters: targets.cluster_count,
        clusters_with_light: learned,
        learn_passes: g.learn_passes,
        guided_fraction: g.guided_fraction,
        rebuilt_at_passes: rebuilds,
        learning_samples: "kept (uniform samples with their correct pdf)",
    })
}

/// The BC6H copies of `--compress bc6h`.
fn compress_step(
    o: &Options,
    img: &LightmapImages,
    probes: Option<&BakeState>,
    log: &mut dyn FnMut(String),
) -> Result<Option<crate::output::compress::CompressionJson>, String> {
    use crate::output::compress;
    if !o.spec.compress_bc6h {
        return Ok(None);
    }
    let mut c = compress::write_bc6h(&o.run.out, img, &o.spec.config.bases, o.spec.config.sg_sharpness, o.spec.compress_signed)?;
    if let (Some(ps), Some(n)) = (probes, o.spec.probes) {
        let valid = ps.valid();
        let coefficients = (0..o.spec.probe_bases.len())
            .map(|b| {
                ps.encoders[b]
                    .iter()
                    .map(|e| {
                        let m = e.coefficients();
                        (0..m.nrows()).map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]).collect()
                    })
                    .collect()
            })
            .collect();
        let grid = compress::ProbeGrid {
            n,
            bases: &o.spec.probe_bases,
            coefficients,
            valid: &valid,
            sg_sharpness: o.spec.config.sg_sharpness,
            signed: o.spec.compress_signed,
        };
        c.probes = compress::write_probe_volumes(&o.run.out, &grid)?;
        for p in &c.probes {
            log(format!(
                "BC6H probes {}: {} volumes, {:.2} B/probe (f32 {:.0}, f16 {:.0}); E/π over 64 normals changes by {:.3} % RMS (f16: {:.4} %){}",
                p.basis,
                p.files.len(),
                p.bytes_per_probe[2],
                p.bytes_per_probe[0],
                p.bytes_per_probe[1],
                100.0 * p.irradiance_rel_rms_bc6h,
                100.0 * p.irradiance_rel_rms_f16,
                compress::SignedAlternativeJson::note(p.signed_alternative.as_ref())
            ));
        }
    }
    for b in &c.bases {
        log(format!(
            "BC6H {}: {:.1} B/texel (f32 {:.0}, f16 {:.0}); E/π at the normal changes by {:.3} % RMS (f16: {:.4} %); error against the bake's E/π f32 / f16 / BC6H {:.2} / {:.2} / {:.2} %{}",
            b.basis,
            b.bytes_per_texel[2],
            b.bytes_per_texel[0],
            b.bytes_per_texel[1],
            100.0 * b.irradiance_rel_rms_bc6h,
            100.0 * b.irradiance_rel_rms_f16,
            100.0 * b.error_at_normal_rel_rms[0],
            100.0 * b.error_at_normal_rel_rms[1],
            100.0 * b.error_at_normal_rel_rms[2],
            compress::SignedAlternativeJson::note(b.signed_alternative.as_ref())
        ));
    }
    Ok(Some(c))
}

/// The engine formats of `--engine-formats`, from the SH L1 lightmap.
fn engine_step(
    o: &Options,
    img: &LightmapImages,
    log: &mut dyn FnMut(String),
) -> Result<Vec<crate::output::engine::EngineFormatJson>, String> {
    if o.spec.engine_formats.is_empty() {
        return Ok(Vec::new());
    }
    let b = o.spec.config.bases.iter().position(|b| *b == crate::accumulate::BasisId::Sh1).ok_or("--engine-formats needs the sh1 basis")?;
    let sh2 = o.spec.config.bases.iter().position(|b| *b == crate::accumulate::BasisId::Sh2).map(|i| img.coefficients[i].as_slice());
    let out = crate::output::engine::write_engine_formats(
        &o.run.out,
        img,
        &img.coefficients[b],
        sh2,
        &o.spec.engine_formats,
        o.spec.engine_frame,
        o.spec.compress_bc6h,
    )?;
    for f in &out {
        f.log_lines().into_iter().for_each(&mut *log);
    }
    Ok(out)
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn write_outputs(
    o: &Options,
    scene: &Scene,
    bvh: &Bvh,
    lm: &Lightmap,
    targets: &Targets,
    state: &BakeState,
    probes: Option<&BakeState>,
    ctx: &OutputContext,
    log: &mut dyn FnMut(String),
) -> Result<(), String> {
    let OutputContext { probe_positions, relocated, device, pipeline, glossy, t0, times } = *ctx;
    let mut img = LightmapImages::new(lm, targets, state);
    let lm_validity = validity_json(state);
    let (filter_json, overlapped, empty) = filter_account(o, lm, state, &img, log);
    log(format!(
        "validity: {} of {} texels inside geometry (back-face fraction > {}) left invalid and dilated over; {} back-face and {} non-finite samples rejected",
        lm_validity.invalid, targets.items.len(), crate::accumulate::MAX_BACK_FACE_FRACTION, lm_validity.back_face_samples, lm_validity.non_finite_samples
    ));
    let fit_ratios = crate::post::refit::solver_step(&mut img, &o.spec.config, &lm.texel_charts, log)?;
    // Denoise (optional) before dilation: the filter reads valid texels only.
    let denoised = denoise_step(o, &mut img, lm, log)?;
    let (dilated, seams, seam_seconds) = seams_step(o, scene, lm, &mut img, log);
    let t_out = Instant::now();
    let ratios = crate::post::refit::irradiance_ratios(&img, &o.spec.config.bases, o.spec.config.sg_sharpness, &lm.texel_charts);
    let files = output::write_lightmap(&o.run.out, &img, &o.spec.config)?;
    let engine_formats = engine_step(o, &img, log)?;
    let compression = compress_step(o, &img, probes, log)?;
    let png = output::preview(scene, bvh, lm, &img, o.spec.preview_width, o.spec.config.camera.map(|c| c.camera));
    png.save(o.run.out.join("preview.png")).map_err(|e| format!("preview.png: {e}"))?;
    let runtime = write_runtime(o, glossy, log)?;
    log(format!("outputs: images, preview and runtime written in {:.2} s", t_out.elapsed().as_secs_f64()));
    let stage_seconds = StageSecondsJson {
        lightmap_passes: times.lightmap_passes,
        probe_passes: times.probe_passes,
        denoise: denoised.as_ref().map(|d| d.seconds),
        seams: seam_seconds,
        outputs: t_out.elapsed().as_secs_f64(),
    };
    let probes = match probes {
        Some(ps) => Some(write_probes(o, ps, probe_positions, relocated, log)?),
        None => None,
    };
    let meta = BakeJson {
        scene: scene.name.clone(),
        spec: serde_json::to_value(&o.spec).expect("a bake spec serialises"),
        device: device.to_string(),
        pipeline,
        passes: state.passes,
        seed: o.spec.config.seed,
        sampler: o.spec.config.sampler.name(),
        adaptive: o.spec.config.adaptive.map(|a| AdaptiveJson {
            pilot_passes: a.pilot_passes,
            batch_fraction: a.batch_fraction,
            floor: a.floor,
            max_per_batch: a.max_per_batch,
        }),
        paths: state.moments.iter().map(crate::accumulate::Moments::count).sum::<u64>(),
        max_bounces: o.spec.config.max_bounces,
        indirect_only: o.spec.config.indirect_only,
        material_maps: scene.has_textures().then(|| crate::output::bake_json::MapsJson {
            textures: scene.textures.len(),
            bytes: scene.textures.iter().map(crate::scene::texture::Texture::bytes).sum(),
            materials: scene.materials.iter().filter(|m| !m.maps.is_empty()).count(),
        }),
        solver: format!("{:?}", o.spec.config.solver),
        layout: LayoutJson {
            width: lm.width,
            height: lm.height,
            texels_per_unit: f64::from(lm.texels_per_unit),
            padding: lm.padding,
            valid_texels: lm.valid_count(),
            utilisation: lm.utilisation(),
            dilated_texels: dilated,
            validity: "alpha channel of every EXR: 1 = baked, 0 = empty, inside geometry or dilated",
            texel_validity: lm_validity,
            overlapped_texels: overlapped,
            empty_before_dilation: empty,
        },
        filter: filter_json,
        irradiance: FileJson { file: "irradiance.exr", quantity: "E/pi (linear RGB)", standard_error: Some("irradiance_se.exr") },
        normals: FileJson {
            file: "normals.exr",
            quantity: "world-space unit shading normal per texel (the basis frame's +Z)",
            standard_error: None,
        },
        bases: bases_json(o, &fit_ratios, &ratios),
        guiding: guiding_json(o, targets, state),
        denoise: denoised,
        seams,
        engine_formats,
        compression,
        stage_seconds,
        meshes: output::mesh_mapping(scene, lm),
        runtime,
        profile: o.spec.profile.as_ref().map(|p| ProfileJson {
            name: p.name.clone(),
            summary: p.summary(),
            lightmap_bases: p.lightmap_bases.iter().map(|b| b.name().to_string()).collect(),
            probe_bases: p.probe_bases.iter().map(|b| b.name().to_string()).collect(),
            specular: p.specular,
            roughness: p.roughness.map(|(a, b)| [a, b]),
            precision: p.precision.clone(),
            language: p.language.clone(),
        }),
        files,
        preview: "preview.png",
        seconds: t0.elapsed().as_secs_f64(),
        peak_memory_bytes: super::limits::peak_memory(),
        probes,
    };
    std::fs::write(o.run.out.join("bake.json"), serde_json::to_string_pretty(&meta).expect("json"))
        .map_err(|e| format!("bake.json: {e}"))?;
    log(format!(
        "wrote {} ({} EXR files, bake.json, preview.png, runtime.wgsl{})",
        o.run.out.display(),
        meta.files.len(),
        if meta.probes.is_some() { ", probes.json" } else { "" }
    ));
    Ok(())
}

/// bake.json's account of the samples a state accepted and rejected.
fn validity_json(st: &BakeState) -> ValidityJson {
    let sum = |f: &dyn Fn(&crate::accumulate::Moments) -> u64| st.moments.iter().map(f).sum::<u64>();
    ValidityJson {
        invalid: st.valid().iter().filter(|v| !**v).count(),
        max_back_face_fraction: crate::accumulate::MAX_BACK_FACE_FRACTION,
        back_face_samples: sum(&|m| m.back_faces),
        non_finite_samples: sum(&|m| m.non_finite),
        accepted_samples: sum(&|m| m.accepted),
    }
}

/// The filtered accumulation's account (null without a filter), and the texels a chart
/// overlaps and those of them empty before dilation.
fn filter_account(
    o: &Options,
    lm: &Lightmap,
    state: &BakeState,
    img: &LightmapImages,
    log: &mut dyn FnMut(String),
) -> (Option<FilterJson>, usize, usize) {
    // Texels a chart overlaps that hold no value before dilation (with a filter, fewer:
    // uncovered edge texels gather their neighbours' samples).
    let overlapped = lm.texel_charts.iter().filter(|c| **c != crate::layout::lightmap::NO_CHART).count();
    let empty =
        (0..lm.texels.len()).filter(|t| lm.texel_charts[*t] != crate::layout::lightmap::NO_CHART && img.validity[*t] == 0.0).count();
    let filter_json = match (&o.spec.config.filter, &state.filtered) {
        (Some(f), Some(fs)) => {
            let uncovered = overlapped - lm.valid_count();
            log(format!(
                "filter: {} radius {} texels over {} gather targets ({uncovered} overlapped but uncovered); {empty} of {overlapped} overlapped texels empty before dilation; {} negative-weight samples not gathered",
                f.name(),
                f.radius,
                fs.moments.len(),
                fs.negative_weights
            ));
            Some(FilterJson {
                kernel: f.name(),
                radius_texels: f64::from(f.radius),
                gather_targets: fs.moments.len(),
                uncovered_targets: uncovered,
                negative_weight_samples_skipped: fs.negative_weights,
                method: "gather-based filtered accumulation ([Roughton19 §3.2]): every texel a chart overlaps gathers the samples of its chart within the radius, weight x filter weight into its own encoders and weighted Welford moments; negative filter weights (Mitchell's lobes) are not gathered (the encoders need positive weights)",
            })
        }
        _ => None,
    };
    (filter_json, overlapped, empty)
}

/// Joint NLM denoising of the images when asked for; its account for bake.json.
fn denoise_step(o: &Options, img: &mut LightmapImages, lm: &Lightmap, log: &mut dyn FnMut(String)) -> Result<Option<DenoiseJson>, String> {
    Ok(match o.spec.denoise {
        Some(opts) => {
            let t = Instant::now();
            let st = crate::post::denoise::denoise(img, lm, opts)?;
            let secs = t.elapsed().as_secs_f64();
            log(format!(
                "denoise: joint NLM over {} texels (window {}, patch {}, k {}), {:.1} effective neighbours on average, {secs:.2} s",
                st.texels,
                2 * opts.radius + 1,
                2 * opts.patch + 1,
                opts.strength,
                st.mean_effective_neighbours
            ));
            Some(DenoiseJson {
                method: "joint non-local means (Rousselle et al. 2012 patch distance; position, normal, chart guides)",
                window: 2 * opts.radius + 1,
                patch: 2 * opts.patch + 1,
                strength: f64::from(opts.strength),
                texels: st.texels,
                mean_effective_neighbours: st.mean_effective_neighbours,
                seconds: secs,
            })
        }
        None => None,
    })
}

/// Seams: the metric on the dilated images (what a runtime's bilinear lookups read),
/// before and (when asked for) after stitching; dilates the images. Returns the dilated
/// texels, bake.json's account and the seconds taken.
fn seams_step(o: &Options, scene: &Scene, lm: &Lightmap, img: &mut LightmapImages, log: &mut dyn FnMut(String)) -> (usize, SeamsJson, f64) {
    let t = Instant::now();
    let seam_edges = crate::post::seams::find_seams(scene, lm);
    let seam_samples = crate::post::seams::samples(&seam_edges, lm.width, lm.height);
    let mut plain = img.clone();
    plain.dilate(o.spec.padding + 1);
    let metric_before = crate::post::seams::seam_metric(&plain, &seam_samples);
    let noise = {
        let (mut s, mut n) = (0.0f64, 0usize);
        for x in &seam_samples {
            for (t, _) in x.a.iter().chain(&x.b) {
                if img.validity[*t] > 0.0 {
                    s += img.standard_error[*t].iter().map(|v| *v as f64).sum::<f64>() / 3.0;
                    n += 1;
                }
            }
        }
        s / n.max(1) as f64
    };
    let metric = "mean |E/pi lookup A - lookup B| over seam samples and channels, after dilation";
    let mut seams = SeamsJson {
        edges: seam_edges.len(),
        samples: seam_samples.len(),
        metric_before,
        metric_after: None,
        texel_noise: noise,
        stitched: false,
        texels: None,
        cg_iterations: None,
        cg_converged: None,
        held_texels: None,
        seconds: None,
        metric,
    };
    let dilated = if o.spec.stitch_seams && !seam_samples.is_empty() {
        let st = crate::post::seams::stitch(img, &plain, &seam_samples);
        let dilated = img.dilate_keeping(o.spec.padding + 1, &st.written_empty);
        let after = crate::post::seams::seam_metric(img, &seam_samples);
        let secs = t.elapsed().as_secs_f64();
        log(format!(
            "seams: {} edges, {} samples; mean |ΔE/π| across them {metric_before:.3e} → {after:.3e} (texel noise {noise:.3e}), {} texels solved in ≤ {} CG iterations, {} held where E/π would go negative{}, {secs:.2} s",
            seam_edges.len(),
            seam_samples.len(),
            st.texels,
            st.iterations,
            st.held,
            if st.converged { "" } else { " (NOT converged to 1e-7: the result is the last iterate)" }
        ));
        seams = SeamsJson {
            metric_after: Some(after),
            stitched: true,
            texels: Some(st.texels),
            cg_iterations: Some(st.iterations),
            cg_converged: Some(st.converged),
            held_texels: Some(st.held),
            seconds: Some(secs),
            ..seams
        };
        dilated
    } else {
        log(format!(
            "seams: {} edges, mean |ΔE/π| across them {metric_before:.3e} (texel noise {noise:.3e}); not stitched, {:.2} s",
            seam_edges.len(),
            t.elapsed().as_secs_f64()
        ));
        img.dilate(o.spec.padding + 1)
    };
    (dilated, seams, t.elapsed().as_secs_f64())
}

/// bake.json's account of each lightmap basis: lobes, domain, solver, frame, files.
fn bases_json(o: &Options, fit: &[IrradianceRatio], written: &[IrradianceRatio]) -> Vec<BasisJson> {
    o
        .spec.config
        .bases
        .iter()
        .zip(fit.iter().zip(written))
        .map(|(b, (fit, written))| {
            let lobes = b.lobes();
            let files: Vec<String> = (0..lobes).map(|l| format!("{}_{l:02}.exr", b.name())).collect();
            let solver = match o.spec.config.solver {
                Solver::Nnls if b.non_negative() => "progressive NNLS",
                Solver::NnlsIrradiance if b.non_negative() => "progressive LS, refitted per texel as NNLS with E/π at the normal pinned",
                Solver::NnlsRescaled if b.non_negative() => "progressive NNLS, lobes scaled per texel to the texel's E/π at the normal",
                _ => "progressive LS",
            };
            BasisJson {
                name: b.name(),
                lobes,
                domain: if b.is_sphere() { "sphere" } else { "upper hemisphere" },
                solver,
                space: "tangent: normal +Z, tangent frame of Duff et al. 2017 (sbf::basis::ambient_dice_bezier::tangent_frame, WGSL tangent_frame) about the texel's shading normal in normals.exr (world space, the normalised mean of the interpolated vertex normals at its sub-texel points)",
                files,
                mirrored_lower_hemisphere: b.is_sphere(),
                sg_sharpness: b.is_sg().then_some(o.spec.config.sg_sharpness),
                lobe_axes: {
                    let axes = b.axes();
                    (!axes.is_empty()).then(|| axes.iter().map(|a| a.to_array()).collect())
                },
                irradiance_ratio: IrradianceRatioJson {
                    mean: written.mean,
                    worst_chart: written.worst_chart,
                    worst_chart_ratio: written.worst_chart_ratio,
                    worst_chart_texels: written.worst_chart_texels,
                    fit_mean: fit.mean,
                    fit_worst_chart_ratio: fit.worst_chart_ratio,
                },
            }
        })
        .collect()
}

/// Writes probes.json (positions, coefficients, validity, relocations); bake.json's account.
fn write_probes(
    o: &Options,
    ps: &BakeState,
    probe_positions: &[Vec3],
    relocated: &[(usize, Vec3)],
    log: &mut dyn FnMut(String),
) -> Result<ProbesSummaryJson, String> {
    let (mean, se, valid) = (ps.mean(), ps.standard_error(), ps.valid());
    let xyz = |p: Vec3| [f64::from(p.x), f64::from(p.y), f64::from(p.z)];
    let probes = probe_positions
        .iter()
        .enumerate()
        .map(|(k, p)| ProbeJson {
            position: xyz(*p),
            mean_radiance: mean[k],
            standard_error: se[k],
            coefficients: o
                .spec
                .probe_bases
                .iter()
                .enumerate()
                .map(|(b, kind)| {
                    let c = ps.encoders[b][k].coefficients();
                    (kind.name(), (0..c.nrows()).map(|i| [c[(i, 0)], c[(i, 1)], c[(i, 2)]]).collect())
                })
                .collect(),
            valid: valid[k],
            back_face_fraction: ps.moments[k].back_face_fraction(),
            relocated_from: relocated.iter().find(|r| r.0 == k).map(|(_, from)| xyz(*from)),
        })
        .collect();
    let file =
        ProbesJson { space: "world (+Y up)", passes: ps.passes, bases: o.spec.probe_bases.iter().map(|b| b.name()).collect(), probes };
    std::fs::write(o.run.out.join("probes.json"), serde_json::to_string_pretty(&file).expect("json"))
        .map_err(|e| format!("probes.json: {e}"))?;
    let validity = validity_json(ps);
    log(format!("probes: {} of {} inside geometry (flagged \"valid\": false in probes.json)", validity.invalid, probe_positions.len()));
    Ok(ProbesSummaryJson { file: "probes.json", count: probe_positions.len(), validity, relocated: relocated.len() })
}
