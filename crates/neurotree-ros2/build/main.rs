//! Generates the Rust types of the ROS 2 interfaces from their definitions under
//! `interfaces/`: `interfaces/<package>/{msg,srv,action}/*` is module `msg::<package>`,
//! and `interfaces/<package>/<release>/{msg,srv,action}/*` (the layouts a later Nav2
//! release changed) is module `msg::<package>::<release>`. Each becomes
//! `$OUT_DIR/<package>.rs` or `$OUT_DIR/<package>_<release>.rs`, which the module
//! includes.

mod idl;
mod rust;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use idl::{Interface, Kind};
use rust::{Definitions, Origin};

const KINDS: [Kind; 3] = [Kind::Message, Kind::Service, Kind::Action];

fn main() -> ExitCode {
    let root = PathBuf::from(env("CARGO_MANIFEST_DIR")).join("interfaces");
    let out = PathBuf::from(env("OUT_DIR"));
    println!("cargo::rerun-if-changed=interfaces");
    match run(&root, &out) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            // Cargo shows a failed build script's output: the file and what to do.
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}

fn env(name: &str) -> String {
    // Cargo sets both for every build script.
    std::env::var(name).unwrap_or_else(|_| panic!("cargo sets {name} for build scripts"))
}

fn run(root: &Path, out: &Path) -> Result<(), String> {
    let mut all = Definitions::new();
    for package in folders(root)? {
        let name = file_name(&package);
        all.insert(origin(&name, None), read_definitions(&package)?);
        for release in folders(&package)? {
            let release_name = file_name(&release);
            if KINDS.iter().any(|k| k.folder() == release_name) {
                continue;
            }
            let definitions = read_definitions(&release)?;
            all.insert(origin(&name, Some(release_name)), definitions);
        }
    }
    for origin in all.keys() {
        let code = rust::generate(&all, origin)?;
        let file = match &origin.release {
            Some(release) => format!("{}_{release}.rs", origin.package),
            None => format!("{}.rs", origin.package),
        };
        let path = out.join(file);
        fs::write(&path, code).map_err(|e| format!("{}: error: {e}", path.display()))?;
    }
    Ok(())
}

fn origin(package: &str, release: Option<String>) -> Origin {
    Origin {
        package: package.to_owned(),
        release,
    }
}

/// The definitions of one folder's `msg`, `srv` and `action`, sorted by name within each.
fn read_definitions(folder: &Path) -> Result<Vec<Interface>, String> {
    let mut interfaces = Vec::new();
    for kind in KINDS {
        let dir = folder.join(kind.folder());
        if !dir.is_dir() {
            continue;
        }
        let mut files: Vec<PathBuf> = entries(&dir)?
            .into_iter()
            .filter(|p| p.extension().is_some_and(|e| e == kind.folder()))
            .collect();
        files.sort();
        for file in files {
            let text =
                fs::read_to_string(&file).map_err(|e| format!("{}: error: {e}", file.display()))?;
            interfaces.push(idl::parse(&file, kind, &text).map_err(|e| e.to_string())?);
        }
    }
    Ok(interfaces)
}

fn folders(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut folders: Vec<PathBuf> = entries(dir)?.into_iter().filter(|p| p.is_dir()).collect();
    folders.sort();
    Ok(folders)
}

fn entries(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let read = fs::read_dir(dir).map_err(|e| format!("{}: error: {e}", dir.display()))?;
    read.map(|entry| entry.map(|e| e.path()))
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{}: error: {e}", dir.display()))
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
