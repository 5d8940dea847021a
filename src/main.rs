//! The `quadlay` command line; see shared/spec/cli.md. Exit status: 0 success, 2 bad input
//! (one `error:` line on standard error naming the file), 1 anything else.

use quadlay::clock::now;
use quadlay::io::{read_mesh_with_resources, write_glb, write_gltf, write_obj, write_ply, LoadedMesh, Polygons};
use quadlay::field::{propose_layout, LayoutOptions, Proposal, ProposeError};
use quadlay::layout::{build_layout_on, parse_layout, write_layout, ChartType, Layout, MeshCounts, Numbering, SurfaceLayout};
use quadlay::mesh::{repair_mesh, Mesh, RepairOptions};
use quadlay::param::{input_uv::input_corner_uv, ParamError, ParamOptions, ParamSession};
use quadlay::quad::{check_edge_length, default_edge_length, QuadError, QuadOptions};
use quadlay::quote::{printable, quoted};
use quadlay::quad::density::edge_length_for_quads;
use quadlay::report::{extract_and_report, Seconds};
use quadlay::summary::{LayoutSummary, MeshSummary};
use std::path::Path;
use std::process::ExitCode;

mod outputs;

const USAGE: &str = "usage:
  quadlay remesh MESH --layout LAYOUT|auto [options]
                              parameterize MESH with the layout and extract a pure quad mesh
      --edge-length L         target quad edge length: about surface area / L² quads
                              (default 1/40 of the bounding-box diagonal)
      --quads N               about N quads (L = √(surface area / N)); not with --edge-length
      --iterations K          chart-optimization iterations (default 3)
      --chart quad|rect|unit  chart of faces without a `patches` entry (default: the layout's)
      --no-align              ignore the layout's alignment tags
      -o, --out FILE          the quad mesh: .obj, .ply (quads), .glb, .gltf (triangles)
      --param-out FILE.obj    the input mesh with per-corner parameter coordinates
      --report FILE.json      the run report (- for standard output)
  quadlay layout MESH -o LAYOUT.json [options]
                              propose a coarse quad layout from the surface's cross field
      --patches N             about how many faces the layout should have
      --feature-angle DEG     sharp edges (tagged layout edges) bend more than DEG (default 35)
  quadlay check MESH [--layout LAYOUT]
                              read and validate a mesh (OBJ, PLY, STL, glTF/GLB) and a layout
                              (shared/spec/layout-format.md), print a summary
  repairs, for check, remesh and layout:
      --keep-largest          keep only the largest connected component
      --fill-holes N          close every boundary loop of at most N edges
  quadlay --help | --version";

/// An error and the exit status it means.
struct Failure {
    code: u8,
    message: String,
}

fn bad_input(message: String) -> Failure {
    Failure { code: 2, message }
}

/// Writes `text` to standard output. A closed pipe (`quadlay remesh ... --report - | head`) is
/// an error with exit status 1, where `print!` would panic.
fn say(text: &str) -> Result<(), Failure> {
    use std::io::Write;
    if !outputs::stdout_is_open() {
        return Err(Failure { code: 1, message: "standard output is closed".into() });
    }
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Failure { code: 1, message: format!("standard output: cannot write: {e}") })
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            // File names come from the command line as they are: no control byte reaches
            // the terminal, and the message stays one line.
            eprintln!("error: {}", printable(&f.message));
            ExitCode::from(f.code)
        }
    }
}

fn run(args: &[String]) -> Result<(), Failure> {
    match args.first().map(String::as_str) {
        Some("check") => check(&args[1..]),
        Some("remesh") => remesh(&args[1..]),
        Some("layout") => layout(&args[1..]),
        Some("--help") | Some("-h") => {
            say(&format!("{USAGE}\n"))
        }
        Some("--version") => {
            say(&format!("quadlay {}\n", env!("CARGO_PKG_VERSION")))
        }
        Some(other) => Err(bad_input(format!("unknown command {} (quadlay --help lists them)", quoted(other)))),
        None => Err(bad_input("no command given (quadlay --help lists them)".into())),
    }
}

fn check(args: &[String]) -> Result<(), Failure> {
    let mut mesh_path = None;
    let mut layout_path = None;
    let mut repairs = RepairOptions::default();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if repair_option(a, &mut it, &mut repairs)? {
            continue;
        }
        match a.as_str() {
            "--layout" => {
                let p = it.next().ok_or_else(|| bad_input("--layout needs a file".into()))?;
                layout_path = Some(p);
            }
            _ if a.starts_with('-') => return Err(bad_input(format!("check: unknown option {}", quoted(a)))),
            _ if mesh_path.is_some() => return Err(bad_input("check takes one mesh file".into())),
            _ => mesh_path = Some(a),
        }
    }
    let path = mesh_path.ok_or_else(|| bad_input("check needs a mesh file".into()))?;
    let (loaded, numbering) = load_repaired(path, &repairs)?;
    let layout = layout_path.map(|lp| place_layout(&loaded.mesh, numbering, lp, read_layout(lp)?)).transpose()?;
    let mut text = format!("mesh:           {path}\n{}", MeshSummary::of(&loaded));
    if let (Some(lp), Some(layout)) = (layout_path, layout) {
        text += &format!("layout:         {lp}\n{}", LayoutSummary::of(&layout));
    }
    say(&text)
}

fn read_layout(path: &str) -> Result<Layout, Failure> {
    let text = std::fs::read_to_string(path).map_err(|e| bad_input(format!("{path}: cannot read: {e}")))?;
    parse_layout(&text).map_err(|e| bad_input(format!("{path}: {e}")))
}

/// Places `layout` on `mesh`; its `mesh` entry may name the mesh as read or as repaired.
fn place_layout(mesh: &Mesh, numbering: Numbering, path: &str, layout: Layout) -> Result<SurfaceLayout, Failure> {
    build_layout_on(mesh, &layout, numbering).map_err(|e| bad_input(format!("{path}: {e}")))
}

/// Takes `--keep-largest` or `--fill-holes N` (cli.md, "Repairs the user asks for") into
/// `options`; false when `arg` is neither.
fn repair_option<'a>(
    arg: &str,
    rest: &mut impl Iterator<Item = &'a String>,
    options: &mut RepairOptions,
) -> Result<bool, Failure> {
    match arg {
        "--keep-largest" => options.keep_largest = true,
        "--fill-holes" => {
            let v = rest.next().ok_or_else(|| bad_input("--fill-holes needs a number of edges".into()))?;
            let n: usize =
                v.parse().map_err(|_| bad_input(format!("--fill-holes: {} is not a whole number", quoted(v))))?;
            if n < 3 {
                return Err(bad_input(format!("--fill-holes: {n} edges make no hole (a hole has at least 3)")));
            }
            options.fill_holes = Some(n);
        }
        _ => return Ok(false),
    }
    Ok(true)
}

/// Loads the mesh at `path`, makes the repairs asked for and refines it where it is coarse
/// ([`LoadedMesh::refined`]); also returns the vertex numbering layout files use on it.
fn load_repaired(path: &str, options: &RepairOptions) -> Result<(LoadedMesh, Numbering), Failure> {
    let loaded = load(path)?;
    let as_read = MeshCounts::of(&loaded.mesh);
    let repaired = if options.is_none() {
        loaded
    } else {
        let (mesh, repairs) = repair_mesh(&loaded.mesh, &loaded.repairs, options)
            .map_err(|e| bad_input(format!("{path}: the repairs asked for do not give a valid mesh: {e}")))?;
        LoadedMesh { mesh, repairs, format: loaded.format }
    };
    let numbering = Numbering { as_read, numbered: MeshCounts::of(&repaired.mesh) };
    Ok((repaired.refined(), numbering))
}

/// The options of `remesh` (cli.md).
#[derive(Default)]
struct RemeshArgs {
    mesh: Option<String>,
    layout: Option<String>,
    edge_length: Option<f64>,
    quads: Option<f64>,
    iterations: Option<usize>,
    chart: Option<ChartType>,
    no_align: bool,
    out: Option<String>,
    param_out: Option<String>,
    report: Option<String>,
    repairs: RepairOptions,
}

/// The kind of quad mesh file an output name asks for, by its extension.
#[derive(Clone, Copy)]
enum OutFormat {
    Obj,
    Ply,
    Glb,
    Gltf,
}

fn out_format(path: &str) -> Result<OutFormat, Failure> {
    let lower = path.to_ascii_lowercase();
    let ext = lower.rsplit('.').next().unwrap_or("");
    match ext {
        "obj" => Ok(OutFormat::Obj),
        "ply" => Ok(OutFormat::Ply),
        "glb" => Ok(OutFormat::Glb),
        "gltf" => Ok(OutFormat::Gltf),
        _ => Err(bad_input(format!("{path}: --out must end in .obj, .ply, .glb or .gltf"))),
    }
}

fn parse_remesh(args: &[String]) -> Result<RemeshArgs, Failure> {
    let mut r = RemeshArgs::default();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if repair_option(a, &mut it, &mut r.repairs)? {
            continue;
        }
        let mut value = |name: &str| it.next().cloned().ok_or_else(|| bad_input(format!("{name} needs a value")));
        match a.as_str() {
            "--layout" => r.layout = Some(value("--layout")?),
            "--edge-length" => {
                let v = value("--edge-length")?;
                let l: f64 = v.parse().map_err(|_| bad_input(format!("--edge-length: {} is not a number", quoted(&v))))?;
                if !(l.is_finite() && l > 0.0) {
                    return Err(bad_input(format!("--edge-length must be a positive number, not {}", quoted(&v))));
                }
                r.edge_length = Some(l);
            }
            "--quads" => {
                let v = value("--quads")?;
                let n: u64 = v.parse().map_err(|_| bad_input(format!("--quads: '{v}' is not a whole number")))?;
                if n == 0 {
                    return Err(bad_input("--quads must be at least 1".into()));
                }
                r.quads = Some(n as f64);
            }
            "--iterations" => {
                let v = value("--iterations")?;
                let k: usize = v.parse().map_err(|_| bad_input(format!("--iterations: {} is not a whole number", quoted(&v))))?;
                if k > 1000 {
                    return Err(bad_input(format!("--iterations: {k} is more than 1000")));
                }
                r.iterations = Some(k);
            }
            "--chart" => {
                let v = value("--chart")?;
                r.chart = Some(match v.as_str() {
                    "quad" => ChartType::Quad,
                    "rect" => ChartType::Rect,
                    "unit" => ChartType::Unit,
                    _ => return Err(bad_input(format!("--chart: {} is not one of quad, rect, unit", quoted(&v)))),
                });
            }
            "--no-align" => r.no_align = true,
            "-o" | "--out" => {
                let v = value("--out")?;
                out_format(&v)?;
                r.out = Some(v);
            }
            "--param-out" => {
                let v = value("--param-out")?;
                if !v.to_ascii_lowercase().ends_with(".obj") {
                    return Err(bad_input(format!("{v}: --param-out writes OBJ; give a name ending in .obj")));
                }
                r.param_out = Some(v);
            }
            "--report" => r.report = Some(value("--report")?),
            _ if a.starts_with('-') => return Err(bad_input(format!("remesh: unknown option {}", quoted(a)))),
            _ if r.mesh.is_some() => return Err(bad_input("remesh takes one mesh file".into())),
            _ => r.mesh = Some(a.clone()),
        }
    }
    if r.edge_length.is_some() && r.quads.is_some() {
        return Err(bad_input("give --edge-length or --quads, not both".into()));
    }
    Ok(r)
}

fn remesh(args: &[String]) -> Result<(), Failure> {
    let t0 = now();
    let a = parse_remesh(args)?;
    let mesh_path = a.mesh.as_deref().ok_or_else(|| bad_input("remesh needs a mesh file".into()))?;
    let layout_path = a.layout.as_deref().ok_or_else(|| bad_input("remesh needs --layout LAYOUT".into()))?;
    let report_file = a.report.as_deref().filter(|&r| r != "-");
    let files: Vec<(&str, &str)> =
        [("--out", a.out.as_deref()), ("--param-out", a.param_out.as_deref()), ("--report", report_file)]
            .into_iter()
            .filter_map(|(option, path)| Some((option, path?)))
            .collect();
    outputs::check_distinct(&[("the input mesh", mesh_path), ("the layout", layout_path)], &files)?;
    if a.report.as_deref() == Some("-") && !outputs::stdout_is_open() {
        return Err(Failure { code: 1, message: "--report -: standard output is closed".into() });
    }
    let (loaded, numbering) = load_repaired(mesh_path, &a.repairs)?;
    let mesh = &loaded.mesh;
    let t_load = now();
    let edge_length = match (a.edge_length, a.quads) {
        (Some(l), _) => l,
        (None, Some(n)) => edge_length_for_quads(mesh, n),
        (None, None) => default_edge_length(mesh),
    };
    // `--layout auto`: the layout `quadlay layout` proposes, with its defaults, judged by its
    // quads at this run's edge length.
    let layout_file = if layout_path == "auto" {
        let mut options = LayoutOptions::default();
        options.edge_length = Some(edge_length);
        propose(mesh, mesh_path, &options)?.layout.in_numbering(mesh, numbering)
    } else {
        read_layout(layout_path)?
    };
    let layout = place_layout(mesh, numbering, layout_path, layout_file)?;
    // Refused before the parameterization, which would take its time for nothing.
    check_edge_length(&layout, edge_length).map_err(|e| bad_input(format!("{layout_path}: {e}")))?;
    let t_layout = now();

    let mut options = ParamOptions::DEFAULT;
    options.iterations = a.iterations.unwrap_or(options.iterations);
    options.align = !a.no_align;
    options.default_chart = a.chart;
    let param_failure = |e: ParamError| {
        let code = if matches!(e, ParamError::Solve(_) | ParamError::NotPositiveDefinite { .. }) { 1 } else { 2 };
        Failure { code, message: format!("{mesh_path} with {layout_path}: {e}") }
    };
    let mut param = ParamSession::new(mesh, &layout, &options).map_err(param_failure)?;
    for _ in 0..options.iterations {
        param.step().map_err(param_failure)?;
    }
    param.finish().map_err(param_failure)?;
    let t_param = now();

    let quad_options = QuadOptions::with_edge_length(edge_length);
    // Every extraction error is the input's: a layout that does not make quads, or an
    // edge length that asks for too many.
    let earlier = Seconds {
        load: t_load - t0,
        layout: t_layout - t_load,
        parameterize: t_param - t_layout,
        ..Seconds::default()
    };
    let (quads, mut report) = extract_and_report(mesh, &layout, &param, &quad_options, earlier)
        .map_err(|e: QuadError| bad_input(format!("{layout_path}: {e}")))?;
    report.input.repairs = loaded.repairs.clone();

    // Every file is written before any is renamed, and the report to standard output goes
    // out in between: a run whose report cannot be written leaves no new file.
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    if let Some(out) = &a.out {
        let faces: Vec<u32> = quads.quads.iter().flatten().copied().collect();
        let polygons = Polygons { positions: &quads.positions, faces: &faces, arity: 4 };
        let bytes = match out_format(out)? {
            OutFormat::Obj => write_obj(polygons, None),
            OutFormat::Ply => write_ply(polygons),
            OutFormat::Glb => write_glb(polygons),
            OutFormat::Gltf => write_gltf(polygons),
        };
        files.push((out.clone(), bytes));
    }
    if let Some(out) = &a.param_out {
        let uv: Vec<[f64; 2]> = input_corner_uv(mesh, &layout, &param).into_iter().flatten().collect();
        let tris: Vec<u32> = mesh.triangles().iter().flatten().copied().collect();
        files.push((out.clone(), write_obj(Polygons { positions: mesh.positions(), faces: &tris, arity: 3 }, Some(&uv))));
    }
    let json = serde_json::to_string_pretty(&report).map_err(|e| Failure { code: 1, message: e.to_string() })?;
    if let Some(path) = a.report.as_deref().filter(|&r| r != "-") {
        files.push((path.to_string(), format!("{json}\n").into_bytes()));
    }
    let staged = outputs::stage(files)?;
    if a.report.as_deref() == Some("-") {
        if let Err(f) = say(&format!("{json}\n")) {
            outputs::discard(staged);
            return Err(f);
        }
    }
    outputs::commit(staged)?;
    if a.report.as_deref() != Some("-") {
        let q = &report.quads;
        let p = &report.parameterization;
        let mut text = format!(
            "{} quads, {} vertices ({} irregular); distortion {:.4} (max {:.3}, {} flipped triangles; lengths off by \
             {:.1}% typically); Hausdorff {:.3}% of the diagonal; {:.2} s\n",
            q.faces,
            q.vertices,
            q.irregular_vertices,
            p.distortion_mean,
            p.distortion_max,
            p.flipped_triangles,
            100.0 * p.length_error,
            100.0 * q.hausdorff,
            report.seconds.total
        );
        for w in &report.warnings {
            text += &format!("warning: {}: {}", w.kind, w.message);
            if let Some([x, y, z]) = w.at {
                text += &format!(" (at {x:.6} {y:.6} {z:.6})");
            }
            text += "\n";
        }
        say(&text)?;
    }
    Ok(())
}

/// The options of `layout` (cli.md).
#[derive(Default)]
struct LayoutArgs {
    mesh: Option<String>,
    out: Option<String>,
    options: LayoutOptions,
    repairs: RepairOptions,
}

fn parse_layout_args(args: &[String]) -> Result<LayoutArgs, Failure> {
    let mut r = LayoutArgs::default();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if repair_option(a, &mut it, &mut r.repairs)? {
            continue;
        }
        let mut value = |name: &str| it.next().cloned().ok_or_else(|| bad_input(format!("{name} needs a value")));
        match a.as_str() {
            "-o" | "--out" => r.out = Some(value("--out")?),
            "--patches" => {
                let v = value("--patches")?;
                let n: usize = v.parse().map_err(|_| bad_input(format!("--patches: '{v}' is not a whole number")))?;
                if !(1..=100_000).contains(&n) {
                    return Err(bad_input(format!("--patches must be between 1 and 100000, not {n}")));
                }
                r.options.patches = Some(n);
            }
            "--feature-angle" => {
                let v = value("--feature-angle")?;
                let d: f64 = v.parse().map_err(|_| bad_input(format!("--feature-angle: '{v}' is not a number")))?;
                if !(d > 0.0 && d < 180.0) {
                    return Err(bad_input(format!("--feature-angle must be between 0 and 180 degrees, not {v}")));
                }
                r.options.feature_angle = d;
            }
            _ if a.starts_with('-') => return Err(bad_input(format!("layout: unknown option '{a}'"))),
            _ if r.mesh.is_some() => return Err(bad_input("layout takes one mesh file".into())),
            _ => r.mesh = Some(a.clone()),
        }
    }
    Ok(r)
}

/// A proposed layout for `mesh` (`quadlay layout`, `remesh --layout auto`).
fn propose(mesh: &Mesh, mesh_path: &str, options: &LayoutOptions) -> Result<Proposal, Failure> {
    propose_layout(mesh, options).map_err(|e| {
        let code = if matches!(e, ProposeError::Field(_)) { 1 } else { 2 };
        Failure { code, message: format!("{mesh_path}: {e}") }
    })
}

fn layout(args: &[String]) -> Result<(), Failure> {
    let t0 = now();
    let a = parse_layout_args(args)?;
    let mesh_path = a.mesh.as_deref().ok_or_else(|| bad_input("layout needs a mesh file".into()))?;
    let out = a.out.as_deref().ok_or_else(|| bad_input("layout needs -o LAYOUT.json".into()))?;
    outputs::check_distinct(&[("the input mesh", mesh_path)], &[("--out", out)])?;
    let (loaded, numbering) = load_repaired(mesh_path, &a.repairs)?;
    let p = propose(&loaded.mesh, mesh_path, &a.options)?;
    let file = write_layout(&p.layout.in_numbering(&loaded.mesh, numbering));
    outputs::commit(outputs::stage(vec![(out.to_string(), file.into_bytes())])?)?;
    let s = &p.surface;
    say(&format!(
        "{} nodes, {} edges ({} tagged), {} faces, {} T-vertices; {} singularities of the cross field; {:.2} s\n",
        s.node_vertex.len(),
        p.layout.edges.len(),
        p.layout.edges.iter().filter(|e| e.align).count(),
        s.faces.len(),
        s.t_vertex_count(),
        p.field.singularities.len(),
        now() - t0
    ))?;
    match p.patches_note(a.options.patches) {
        Some(note) => say(&format!("note: {note}\n")),
        None => Ok(()),
    }
}

fn load(path: &str) -> Result<LoadedMesh, Failure> {
    let bytes = std::fs::read(path).map_err(|e| bad_input(format!("{path}: cannot read: {e}")))?;
    let dir = Path::new(path).parent().map(Path::to_path_buf).unwrap_or_default();
    // glTF may keep its buffers in files beside it; only plain relative names are followed.
    let resource = |uri: &str| {
        if uri.contains("..") || uri.contains(':') || uri.starts_with('/') {
            return None;
        }
        std::fs::read(dir.join(uri)).ok()
    };
    read_mesh_with_resources(&bytes, path, &resource).map_err(|e| bad_input(format!("{path}: {e}")))
}
