//! The `quadlay` command line; see shared/spec/cli.md. Exit status: 0 success, 2 bad input
//! (one `error:` line on standard error naming the file), 1 anything else.

use quadlay::io::read_mesh_with_resources;
use quadlay::layout::{build_layout, parse_layout, SurfaceLayout};
use quadlay::summary::{LayoutSummary, MeshSummary};
use std::path::Path;
use std::process::ExitCode;

const USAGE: &str = "usage:
  quadlay check MESH [--layout LAYOUT]
                              read and validate a mesh (OBJ, PLY, STL, glTF/GLB) and a layout
                              (shared/spec/layout-format.md), print a summary
  quadlay --help | --version";

/// An error and the exit status it means.
struct Failure {
    code: u8,
    message: String,
}

fn bad_input(message: String) -> Failure {
    Failure { code: 2, message }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("error: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}

fn run(args: &[String]) -> Result<(), Failure> {
    match args.first().map(String::as_str) {
        Some("check") => check(&args[1..]),
        Some("--help") | Some("-h") => {
            println!("{USAGE}");
            Ok(())
        }
        Some("--version") => {
            println!("quadlay {}", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
        Some(other) => Err(bad_input(format!("unknown command '{other}' (quadlay --help lists them)"))),
        None => Err(bad_input("no command given (quadlay --help lists them)".into())),
    }
}

fn check(args: &[String]) -> Result<(), Failure> {
    let mut mesh_path = None;
    let mut layout_path = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--layout" => {
                let p = it.next().ok_or_else(|| bad_input("--layout needs a file".into()))?;
                layout_path = Some(p);
            }
            _ if a.starts_with('-') => return Err(bad_input(format!("check: unknown option '{a}'"))),
            _ if mesh_path.is_some() => return Err(bad_input("check takes one mesh file".into())),
            _ => mesh_path = Some(a),
        }
    }
    let path = mesh_path.ok_or_else(|| bad_input("check needs a mesh file".into()))?;
    let loaded = load(path)?;
    let layout = layout_path.map(|lp| load_layout(&loaded.mesh, lp)).transpose()?;
    print!("mesh:           {path}\n{}", MeshSummary::of(&loaded));
    if let (Some(lp), Some(layout)) = (layout_path, layout) {
        print!("layout:         {lp}\n{}", LayoutSummary::of(&layout));
    }
    Ok(())
}

fn load_layout(mesh: &quadlay::mesh::Mesh, path: &str) -> Result<SurfaceLayout, Failure> {
    let text = std::fs::read_to_string(path).map_err(|e| bad_input(format!("{path}: cannot read: {e}")))?;
    let layout = parse_layout(&text).map_err(|e| bad_input(format!("{path}: {e}")))?;
    build_layout(mesh, &layout).map_err(|e| bad_input(format!("{path}: {e}")))
}

fn load(path: &str) -> Result<quadlay::io::LoadedMesh, Failure> {
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
