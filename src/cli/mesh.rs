//! `flank mesh`: both bodies of a scene, decks, VTU, flank parameters, report.

use std::path::PathBuf;

use anyhow::Result;

use crate::cli::common::MeshElement;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.toml).
    scene: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Flank element size (mm); overrides the scene's [mesh] flank_size_mm.
    #[arg(long)]
    flank_size: Option<f64>,
    /// Base element size (mm); overrides the scene's [mesh] base_size_mm.
    #[arg(long)]
    base_size: Option<f64>,
    /// Write the decks without the nominal load.
    #[arg(long)]
    no_load: bool,
    /// Element type; overrides the scene's [mesh] element.
    #[arg(long, value_enum)]
    element: Option<MeshElement>,
    /// Mesher: native (structured, graded to the flank) or gmsh
    /// (unstructured from a size field; needs a build with
    /// `--features gmsh` and libgmsh-dev).
    #[arg(long, value_enum, default_value_t = MesherChoice::Native)]
    mesher: MesherChoice,
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
enum MesherChoice {
    Native,
    Gmsh,
}

pub fn run(args: Args) -> Result<()> {
    let Args {
        scene,
        out,
        flank_size,
        base_size,
        no_load,
        element,
        mesher,
    } = args;
    mesh_scene(
        &scene, &out, flank_size, base_size, !no_load, element, mesher,
    )
}

/// Element counts by CalculiX type name, e.g. {"C3D15": 1234}.
fn elements_by_type(mesh: &flank::fem::mesh::Mesh) -> serde_json::Value {
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    for e in &mesh.elements {
        *counts.entry(e.kind.name().to_string()).or_default() += 1;
    }
    serde_json::json!(counts)
}

/// `flank mesh`: both bodies of a scene, decks, VTU, flank parameters, report.
fn mesh_scene(
    path: &std::path::Path,
    out: &std::path::Path,
    flank_size: Option<f64>,
    base_size: Option<f64>,
    with_load: bool,
    element: Option<MeshElement>,
    mesher: MesherChoice,
) -> Result<()> {
    use flank::geometry::involute::base_radius;
    use flank::mesh::gear_body::{body_model, Mesher, GMSH_AVAILABLE, GMSH_MISSING};
    use flank::mesh::gear_sector::SectorOptions;
    let scene = flank::scene::read_scene(path)?;
    if scene.is_bevel() {
        if mesher == MesherChoice::Gmsh {
            anyhow::bail!(
                "--mesher gmsh: bevel and hypoid bodies are meshed by the native mesher only"
            );
        }
        return mesh_bevel_scene(path, &scene, out, flank_size, base_size, with_load, element);
    }
    let cyl = scene.cylindrical("`flank mesh` of cylindrical gears")?;
    let report = flank::geometry::pair::check_pair(&cyl.pair)?;
    let hex20 = match element {
        Some(e) => e == MeshElement::Hex20,
        None => scene.mesh.element == flank::scene::ElementKind::Hex20,
    };
    let element_kind = if hex20 {
        flank::fem::mesh::ElementKind::C3D20
    } else {
        flank::fem::mesh::ElementKind::C3D15
    };
    if mesher == MesherChoice::Gmsh && !GMSH_AVAILABLE {
        anyhow::bail!("--mesher gmsh: {GMSH_MISSING}");
    }
    let mn = cyl.pair.pinion.normal_module;
    let flank_size = flank_size.or(scene.mesh.flank_size).unwrap_or(mn / 8.0);
    let base_size = base_size.or(scene.mesh.base_size).unwrap_or(mn / 2.0);
    if !(flank_size > 0.0 && base_size >= flank_size) {
        anyhow::bail!(
            "--flank-size / --base-size (or the scene's [mesh] flank_size_mm / base_size_mm): element sizes must satisfy 0 < flank size ({flank_size}) ≤ base size ({base_size})"
        );
    }
    let options = SectorOptions {
        teeth: scene.mesh.teeth_in_sector as usize,
        flank_size,
        base_size,
        face_layers: 0,
        element: element_kind,
    };
    let cos_aw = report.working_pressure_angle_rad.cos();
    let force = scene.load.torque_nmm / base_radius(&cyl.pair.pinion);
    let modifications = cyl.flank_modifications()?;
    // the gears through the gear-pair interface (with their modifications)
    let pair = scene.gear_pair()?;
    let mut bodies = serde_json::Map::new();
    let members = [
        ("pinion", &cyl.pair.pinion, &scene.pinion_material),
        ("gear", &cyl.pair.gear, &scene.gear_material),
    ];
    // both bodies first: a body that cannot be meshed leaves no file behind
    let mut models = Vec::new();
    for (i, (name, spec, material)) in members.into_iter().enumerate() {
        let rb = base_radius(spec);
        let load = (with_load && force > 0.0).then_some((force, rb / cos_aw));
        let mesher = match mesher {
            MesherChoice::Native => Mesher::Native,
            MesherChoice::Gmsh => Mesher::Gmsh(element_kind),
        };
        if let Some(m) = &modifications[i] {
            for w in m.warnings() {
                eprintln!("warning: {name}: {w}");
            }
        }
        models.push(body_model(pair.body(i), material, &options, mesher, load)?);
    }
    std::fs::create_dir_all(out)?;
    for ((name, spec, _), body) in members.into_iter().zip(&models) {
        let rb = base_radius(spec);
        let modified = &body.modification;
        let mesh = &body.model.mesh;
        let flank_nodes = write_body(out, name, &body.model, &body.sector.flank_uv, "node,u,v_mm")?;
        bodies.insert(
            name.to_string(),
            serde_json::json!({
                "nodes": mesh.node_count(),
                "elements": elements_by_type(mesh),
                "flank_nodes": flank_nodes,
                "teeth_in_sector": options.teeth,
                "flank_size_mm": flank_size,
                "base_size_mm": base_size,
                "mesher": if mesher == MesherChoice::Native { "native" } else { "gmsh" },
                "min_scaled_jacobian": body.sector.quality.min_scaled_jacobian,
                "max_aspect_ratio": body.sector.quality.max_aspect_ratio,
                "flank_modification": modified,
                "base_radius_mm": rb,
                "nominal_load": body.load.map(|(n, f)| serde_json::json!({
                    "node": mesh.node_labels[n], "force_n": f, "normal_force_n": force
                })),
            }),
        );
        println!(
            "{name}: {} nodes, {} elements, min scaled Jacobian {:.3}",
            mesh.node_count(),
            mesh.elements.len(),
            body.sector.quality.min_scaled_jacobian
        );
    }
    let summary = serde_json::json!({
        "scene": path.display().to_string(),
        "bodies": bodies,
        "pair": {
            "contact_ratio": report.contact_ratio,
            "overlap_ratio": report.overlap_ratio,
            "working_pressure_angle_deg": report.working_pressure_angle_deg,
        },
    });
    flank::atomic_file::write(
        &out.join("mesh_report.json"),
        serde_json::to_string_pretty(&summary)? + "\n",
    )?;
    println!("wrote {}", out.display());
    Ok(())
}

/// `flank mesh` on a bevel/hypoid scene: both bodies by the bevel sector
/// mesher (hex20, or wedge15 by `--element` or `[mesh] element`), the mounts clamped, the nominal load (the pinion torque
/// on the pinion, the same torque × z2/z1 on the gear) at each middle
/// tooth's drive flank.
fn mesh_bevel_scene(
    path: &std::path::Path,
    scene: &flank::scene::Scene,
    out: &std::path::Path,
    flank_size: Option<f64>,
    base_size: Option<f64>,
    with_load: bool,
    element: Option<MeshElement>,
) -> Result<()> {
    let bevel = scene.bevel("this command on bevel/hypoid pairs")?;
    use flank::mesh::bevel_body::bevel_body_model;
    let options = flank::compliance::body::bevel_sector_options(
        scene,
        &flank::compliance::body::BodyMeshOptions {
            flank_size,
            base_size,
            with_load,
            element: element.map(|e| match e {
                MeshElement::Hex20 => flank::scene::ElementKind::Hex20,
                MeshElement::Wedge15 => flank::scene::ElementKind::Wedge15,
            }),
        },
    )?;
    let (flank_size, base_size) = (options.flank_size, options.base_size);
    let ratio = bevel.blank.z2 / bevel.blank.z1;
    let torques = [scene.load.torque_nmm, scene.load.torque_nmm * ratio];
    let members = [
        ("pinion", &scene.pinion_material),
        ("gear", &scene.gear_material),
    ];
    // both bodies first: a body that cannot be meshed leaves no file behind
    let mut models = Vec::new();
    for (i, (name, material)) in members.iter().enumerate() {
        let torque = with_load.then_some(torques[i]);
        models.push(bevel_body_model(
            &bevel.bodies[i],
            name,
            material,
            &options.member(i == 0),
            torque,
        )?);
    }
    let partial = scene.mesh.teeth_in_sector < bevel.blank_inputs.z1;
    if options.shank.is_some() && partial {
        println!(
            "warning: {}",
            flank::mesh::bevel_sector::SHANK_SECTOR_WARNING
        );
    }
    std::fs::create_dir_all(out)?;
    let mut bodies = serde_json::Map::new();
    for ((name, _), body) in members.iter().zip(&models) {
        let mesh = &body.model.mesh;
        let flank_nodes = write_body(
            out,
            name,
            &body.model,
            &body.sector.flank_uv,
            "node,u_mm,v_mm",
        )?;
        let q = &body.sector.quality;
        bodies.insert(
            name.to_string(),
            serde_json::json!({
                "nodes": mesh.node_count(),
                "elements": elements_by_type(mesh),
                "flank_nodes": flank_nodes,
                "teeth_in_sector": scene.mesh.teeth_in_sector,
                "flank_size_mm": flank_size,
                "base_size_mm": base_size,
                "mesher": "native",
                "lattice": body.sector.counts,
                "mount": body.sector.mount,
                "shank": body.sector.shank,
                "min_scaled_jacobian": q.min_scaled_jacobian,
                "max_aspect_ratio": q.max_aspect_ratio,
                "nominal_load": body.load.map(|(n, f)| serde_json::json!({
                    "node": mesh.node_labels[n],
                    "force_n": f,
                    "normal_force_n": (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt(),
                })),
            }),
        );
        println!(
            "{name}: {} nodes, {} elements, min scaled Jacobian {:.3}, max aspect ratio {:.1}",
            mesh.node_count(),
            mesh.elements.len(),
            q.min_scaled_jacobian,
            q.max_aspect_ratio
        );
    }
    let summary = serde_json::json!({
        "scene": path.display().to_string(),
        "bodies": bodies,
        "pair": {
            "kind": format!("{:?}", scene.kind).to_lowercase(),
            "shaft_angle_deg": bevel.blank.sigma.to_degrees(),
            "offset_mm": bevel.blank.a,
            "teeth": [bevel.blank.z1, bevel.blank.z2],
        },
    });
    flank::atomic_file::write(
        &out.join("mesh_report.json"),
        serde_json::to_string_pretty(&summary)? + "\n",
    )?;
    println!("wrote {}", out.display());
    Ok(())
}

/// Writes a body's deck (`<name>.inp`), VTU and flank parameters
/// (`<name>_flank_uv.csv`, header `header`); returns its flank node count.
fn write_body(
    out: &std::path::Path,
    name: &str,
    model: &flank::fem::model::Model,
    flank_uv: &std::collections::HashMap<usize, (f64, f64)>,
    header: &str,
) -> Result<usize> {
    use std::io::Write;
    let mesh = &model.mesh;
    flank::deck::write_deck(model, &out.join(format!("{name}.inp")))?;
    flank::report::vtu::write_vtu(&out.join(format!("{name}.vtu")), mesh, &[], &[])?;
    let uv_path = out.join(format!("{name}_flank_uv.csv"));
    let mut w = flank::atomic_file::AtomicWriter::create(&uv_path)?;
    writeln!(w, "{header}")?;
    let mut uv: Vec<(&usize, &(f64, f64))> = flank_uv.iter().collect();
    uv.sort_by_key(|(n, _)| **n);
    for (&n, &(u, v)) in uv {
        writeln!(w, "{},{:e},{:e}", mesh.node_labels[n], u, v)?;
    }
    w.commit()?;
    Ok(mesh
        .node_sets
        .iter()
        .filter(|(k, _)| k.starts_with("FLANK_"))
        .map(|(_, v)| v.len())
        .sum())
}
