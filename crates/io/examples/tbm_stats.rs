//! Writes a model file compactly at several quantization steps and prints
//! what each costs (bytes, zstd against the order-0 entropy an ANS coder
//! such as constriction would approach) and its error:
//!
//! `cargo run --release -p trigbody-io --example tbm_stats -- MODEL.json [--mm-per-unit S] [--write OUT.tbm]`

use trigbody_io::model::read_model;
use trigbody_io::tbm::{encode_tbm, TbmOptions, DEFAULT_RELATIVE_STEP};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let (mut path, mut mm, mut write) = (None, 1000.0, None);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--mm-per-unit" => mm = args.next().ok_or("--mm-per-unit needs a value")?.parse()?,
            "--write" => write = Some(args.next().ok_or("--write needs a file")?),
            _ => path = Some(a),
        }
    }
    let path = path.ok_or("usage: tbm_stats MODEL.json [--mm-per-unit S] [--write OUT.tbm]")?;
    let model = read_model(std::io::BufReader::new(std::fs::File::open(&path)?))?;
    let json = std::fs::metadata(&path)?.len();
    println!("{path}: {json} bytes of JSON");
    println!("relative step | step mm | bytes | section numbers | bound mm | max error mm | order-0 entropy B | per-index entropy B");
    for rel in [0.25, 0.5, 1.0, 2.0, 4.0, 8.0] {
        let options = TbmOptions {
            step: model.body.map(|b| rel * DEFAULT_RELATIVE_STEP * b.height),
            ..TbmOptions::default()
        };
        let (bytes, s) = encode_tbm(&model, &options)?;
        println!(
            "{:>5} x default | {:.4} | {} | {} | {:.3} | {:.4} | {:.0} | {:.0}",
            rel,
            s.step * mm,
            s.bytes,
            s.section_numbers,
            s.bound * mm,
            s.max_error * mm,
            s.entropy_bytes,
            s.entropy_by_index_bytes
        );
        if rel == 1.0 {
            if let Some(out) = &write {
                std::fs::write(out, &bytes)?;
            }
        }
    }
    Ok(())
}
