use trigbody_core::scan_section::{CloudSlicer, ScanSectionOptions};
use trigbody_core::section::MeshSlicer;
use trigbody_core::*;
fn cpu() -> f64 {
    let st = std::fs::read_to_string("/proc/thread-self/stat").unwrap();
    let f: Vec<&str> = st.rsplit(')').next().unwrap().split_whitespace().collect();
    (f[11].parse::<f64>().unwrap() + f[12].parse::<f64>().unwrap()) * 10.0
}
fn main() {
    let m = shapes::stick_body(2);
    let c0 = cpu();
    let scan = scanner::virtual_scan(&m, &Default::default()).unwrap();
    println!("scan {} ms cpu", cpu() - c0);
    let cloud = scan.cloud;
    let c0 = cpu();
    for _ in 0..20 {
        std::hint::black_box(CloudSlicer::new(&cloud, Vec3::Z).unwrap());
    }
    println!("slicer {} ms cpu", (cpu() - c0) / 20.0);
    let s = CloudSlicer::new(&cloud, Vec3::Z).unwrap();
    let (lo, hi) = s.range();
    let o = ScanSectionOptions::default();
    let c0 = cpu();
    for _ in 0..20 {
        for k in 0..80 {
            let _ =
                std::hint::black_box(s.section_at(lo + (k as f64 + 0.5) * (hi - lo) / 80.0, &o));
        }
    }
    println!("80 slabs {} ms cpu", (cpu() - c0) / 20.0);
    let c0 = cpu();
    for _ in 0..100 {
        let ms = MeshSlicer::new(&m, Vec3::Z, &Default::default()).unwrap();
        std::hint::black_box(ms.sections_evenly(80));
    }
    println!(
        "80 mesh sections incl. slicer {} ms cpu",
        (cpu() - c0) / 100.0
    );
}
