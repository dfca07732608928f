//! Writing output files: one policy for every command.
//!
//! * An output is never written over one of the command's inputs, not even
//!   with `--force` (the input is what the output was made from): the same
//!   file is found by device and inode, so a hard link or another spelling
//!   of the path is caught too.
//! * Two outputs of one command may not name the same file.
//! * An existing file is replaced only with `--force`; without it the
//!   command stops with exit 2 naming the file.
//! * The bytes go to a temporary file beside the target, which is then
//!   renamed (or, without `--force`, hard-linked) into place
//!   ([`trigbody_io::write_atomically`]): a failure or a killed process
//!   never leaves half a file under the user's name, and a file being
//!   replaced survives every failure.
//! * Missing parent directories are created.
//! * A target that is neither a regular file nor a directory (a device such
//!   as `/dev/null` or `/dev/stdout`, a FIFO) is written in place, with or
//!   without `--force`, in the command's default format when its name has
//!   no extension: writing to it replaces nothing, and a rename would
//!   put a regular file where the device was.

use crate::exit::bad;
use anyhow::Result;
use std::path::Path;

/// Writes `bytes` to `path` under the policy above; `inputs` are the
/// command's input files.
pub fn write_file(path: &Path, bytes: &[u8], inputs: &[&Path], force: bool) -> Result<()> {
    refuse_input(path, inputs)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| bad(format!("{}: {e}", dir.display())))?;
    }
    trigbody_io::write_atomically(path, force, |w| Ok(w.write_all(bytes)?)).map_err(|e| match e {
        trigbody_io::IoError::AlreadyExists { .. } => bad(format!(
            "{}: already exists; use --force to replace it",
            path.display()
        )),
        e => bad(e),
    })
}

/// Whether two paths name one existing file (same device and inode on
/// Unix, so hard links count), or, when neither exists yet, the same name.
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => same_inode(&x, &y, a, b),
        (Err(_), Err(_)) => absolute(a) == absolute(b),
        _ => false,
    }
}

#[cfg(unix)]
fn same_inode(x: &std::fs::Metadata, y: &std::fs::Metadata, _: &Path, _: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    x.dev() == y.dev() && x.ino() == y.ino()
}

#[cfg(not(unix))]
fn same_inode(_: &std::fs::Metadata, _: &std::fs::Metadata, a: &Path, b: &Path) -> bool {
    absolute(a) == absolute(b)
}

/// The path with its directory resolved (the file itself need not exist).
fn absolute(p: &Path) -> Option<std::path::PathBuf> {
    if let Ok(c) = p.canonicalize() {
        return Some(c);
    }
    let dir = match p.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(d) => d.canonicalize().ok()?,
        None => std::env::current_dir().ok()?,
    };
    Some(dir.join(p.file_name()?))
}

/// Exit 2 when `path` is one of `inputs` (by device and inode).
pub fn refuse_input(path: &Path, inputs: &[&Path]) -> Result<()> {
    if trigbody_io::is_special_file(path) {
        return Ok(());
    }
    if inputs.iter().any(|input| same_file(path, input)) {
        return Err(bad(format!(
            "{}: refusing to write over the input file",
            path.display()
        )));
    }
    Ok(())
}

/// Exit 2 when two of a command's outputs name the same file (the second
/// would silently replace the first); devices may repeat.
pub fn refuse_repeated_outputs(outputs: &[(&str, Option<&Path>)]) -> Result<()> {
    let given: Vec<(&str, &Path)> = outputs
        .iter()
        .filter_map(|(flag, p)| p.map(|p| (*flag, p)))
        .collect();
    for (i, (flag_a, a)) in given.iter().enumerate() {
        for (flag_b, b) in &given[i + 1..] {
            if !trigbody_io::is_special_file(a) && same_file(a, b) {
                return Err(bad(format!(
                    "{flag_a} {} and {flag_b} {} name the same file; give each output its own name",
                    a.display(),
                    b.display()
                )));
            }
        }
    }
    Ok(())
}

/// The lower-case extension of an output path; for a device or FIFO
/// without one (`/dev/null`), `default`.
pub fn output_extension(path: &Path, default: &str) -> String {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) => e.to_ascii_lowercase(),
        None if trigbody_io::is_special_file(path) => default.to_string(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_in_place_and_stays_a_device() {
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        assert!(trigbody_io::is_special_file(null));
        for force in [false, true] {
            write_file(null, b"model", &[], force).unwrap();
            let kind = std::fs::metadata(null).unwrap().file_type();
            assert!(kind.is_char_device(), "/dev/null was replaced");
        }
        assert!(!trigbody_io::is_special_file(Path::new("Cargo.toml")));
        assert!(!trigbody_io::is_special_file(Path::new(".")));
    }

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("trigbody-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn new_file_is_written_and_an_existing_one_needs_force() {
        let d = dir("force");
        let p = d.join("sub").join("a.txt");
        write_file(&p, b"one", &[], false).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        let e = write_file(&p, b"two", &[], false).unwrap_err();
        assert!(e.to_string().contains("already exists"), "{e}");
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        write_file(&p, b"two", &[], true).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(p.parent().unwrap()).unwrap().count(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn the_input_is_never_replaced_even_with_force() {
        let d = dir("input");
        let p = d.join("in.obj");
        std::fs::write(&p, b"v 0 0 0").unwrap();
        let same = d.join(".").join("in.obj");
        for force in [false, true] {
            let e = write_file(&same, b"x", &[&p], force).unwrap_err();
            assert!(e.to_string().contains("input file"), "{e}");
        }
        assert_eq!(std::fs::read(&p).unwrap(), b"v 0 0 0");
        std::fs::remove_dir_all(d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_hard_link_to_the_input_is_the_input() {
        let d = dir("link");
        let p = d.join("in.obj");
        std::fs::write(&p, b"v 0 0 0").unwrap();
        let link = d.join("link.obj");
        std::fs::hard_link(&p, &link).unwrap();
        let e = write_file(&link, b"x", &[&p], true).unwrap_err();
        assert!(e.to_string().contains("input file"), "{e}");
        assert_eq!(std::fs::read(&p).unwrap(), b"v 0 0 0");
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn two_outputs_with_one_name_are_refused() {
        let d = dir("twice");
        let a = d.join("a.json");
        let same = d.join(".").join("a.json");
        let e = refuse_repeated_outputs(&[
            ("-o", Some(&a)),
            ("--mesh", None),
            ("--report", Some(&same)),
        ])
        .unwrap_err();
        assert!(e.to_string().contains("name the same file"), "{e}");
        let b = d.join("b.json");
        refuse_repeated_outputs(&[("-o", Some(&a)), ("--report", Some(&b))]).unwrap();
        let null = Path::new("/dev/null");
        refuse_repeated_outputs(&[("-o", Some(null)), ("--report", Some(null))]).unwrap();
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn a_failed_write_leaves_nothing() {
        let d = dir("fail");
        // A directory where the file should go: the rename fails.
        let p = d.join("taken");
        std::fs::create_dir(&p).unwrap();
        assert!(write_file(&p, b"x", &[], true).is_err());
        assert!(p.is_dir());
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(d).unwrap();
    }
}
