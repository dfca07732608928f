//! The rasterizer against exact answers: silhouettes of a cylinder and a
//! sphere in pixels, the side facing the light brighter, colour by value,
//! and every input error.

mod common;

use common::shapes::{capped_cylinder, torus, uv_sphere};
use std::path::Path;
use trigbody_core::{Mesh, MeshError, Vec3};
use trigbody_render::colormap::luminance;
use trigbody_render::{
    render_mesh, render_mesh_values, Render, RenderError, RenderOptions, VertexValues, View,
};

/// Options for measuring: one view, no labels, no supersampling (a pixel is
/// covered exactly when its centre is inside the silhouette).
fn measuring(size: u32, view: View) -> RenderOptions {
    RenderOptions {
        width: size,
        height: size,
        views: vec![view],
        supersample: 1,
        labels: false,
        ..RenderOptions::default()
    }
}

/// Pixels of the panel that differ from the background.
fn covered(render: &Render, panel: usize, background: [u8; 3]) -> Vec<(u32, u32)> {
    let f = &render.frames[panel];
    let mut out = Vec::new();
    for y in 0..f.height {
        for x in f.left..f.left + f.width {
            if render.image.pixel(x, y) != Some(background) {
                out.push((x, y));
            }
        }
    }
    out
}

/// Writes a PNG for a person to look at (best effort: a test never fails
/// because /tmp is not writable).
fn save(render: &Render, name: &str) {
    if let Ok(png) = render.image.to_png() {
        let _ = std::fs::write(std::env::temp_dir().join(name), png);
    }
}

#[test]
fn cylinder_silhouette_is_the_rectangle_2r_by_h() {
    let (r, h) = (0.3, 1.2);
    let mesh = capped_cylinder(r, h, 256);
    assert!(mesh.signed_volume() > 0.0, "outward triangles");
    // At 400 px the rectangle's edges fall on pixel boundaries; at 333 px
    // they do not, so the count there checks the sampling, not just the
    // framing.
    let views = [
        View::front(),
        View::side(),
        View::back(),
        View::azimuth(33.0),
    ];
    let cases = views.into_iter().flat_map(|v| [(400, v.clone()), (333, v)]);
    for (size, view) in cases {
        let options = measuring(size, view.clone());
        let render = render_mesh(&mesh, &options).unwrap();
        let frame = &render.frames[0];
        // A 256-gon's width across any direction is between 2r·cos(π/256)
        // and 2r; the height is exact.
        let (_, y0) = frame.project(Vec3::new(0.0, h, 0.0));
        let (_, y1) = frame.project(Vec3::new(0.0, 0.0, 0.0));
        let (w_px, h_px) = (2.0 * r * frame.pixels_per_unit, (y1 - y0).abs());
        let expected = w_px * h_px;
        let count = covered(&render, 0, options.background).len() as f64;
        let error = (count - expected) / expected;
        println!(
            "cylinder {view} at {size} px: {count} px covered, rectangle {w_px:.1}×{h_px:.1} = {expected:.0} px, error {:+.3} %",
            error * 100.0
        );
        assert!(error.abs() < 0.02, "{view}: coverage error {error}");
        // Framing: the tall side fills the panel up to the margin.
        assert!((h_px - size as f64 * (1.0 - 2.0 * options.margin)).abs() < 1e-9);
    }
}

#[test]
fn faces_towards_the_light_are_brighter() {
    let mesh = capped_cylinder(0.3, 1.2, 128);
    let options = RenderOptions {
        views: vec![View::front()],
        width: 300,
        height: 300,
        labels: false,
        ..RenderOptions::default()
    };
    let render = render_mesh(&mesh, &options).unwrap();
    save(&render, "trigbody_render_cylinder.png");
    let frame = &render.frames[0];
    let (cx, _) = frame.project(Vec3::new(0.0, 0.6, 0.0));
    let (mut left, mut right) = ((0.0, 0), (0.0, 0));
    for (x, y) in covered(&render, 0, options.background) {
        let l = luminance(render.image.pixel(x, y).unwrap());
        if (x as f64 + 0.5) < cx {
            left = (left.0 + l, left.1 + 1);
        } else {
            right = (right.0 + l, right.1 + 1);
        }
    }
    let (left, right) = (left.0 / left.1 as f64, right.0 / right.1 as f64);
    println!("mean luminance: left half {left:.3}, right half {right:.3}");
    assert!(left > 1.3 * right, "left {left} right {right}");
    // With the light moved to the right the order flips.
    let options = RenderOptions {
        light: [0.45, 0.55, 0.7],
        ..options
    };
    let render = render_mesh(&mesh, &options).unwrap();
    let px = |x: f64| luminance(render.image.pixel(x as u32, 150).unwrap());
    let (x0, _) = render.frames[0].project(Vec3::new(-0.25, 0.6, 0.0));
    let (x1, _) = render.frames[0].project(Vec3::new(0.25, 0.6, 0.0));
    assert!(px(x1) > px(x0));
}

#[test]
fn the_mesh_normals_are_used_when_present() {
    // A flat square facing the viewer, its normals tilted towards the light
    // (upper left) or away from it (lower right); the picture follows the
    // normals, not the flat geometry.
    let p = Vec3::new;
    let mut square = Mesh::new(
        vec![p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    let options = measuring(64, View::front());
    let mean_luminance = |mesh: &Mesh| {
        let render = render_mesh(mesh, &options).unwrap();
        let pixels = covered(&render, 0, options.background);
        pixels
            .iter()
            .map(|&(x, y)| luminance(render.image.pixel(x, y).unwrap()))
            .sum::<f64>()
            / pixels.len() as f64
    };
    let computed = mean_luminance(&square);
    square.normals = Some(vec![p(-1., 1., 1.); 4]);
    let towards = mean_luminance(&square);
    square.normals = Some(vec![p(1., -1., 1.); 4]);
    let away = mean_luminance(&square);
    println!(
        "square: computed normals {computed:.3}, towards the light {towards:.3}, away {away:.3}"
    );
    assert!(towards > computed && computed > away);
}

#[test]
fn either_winding_shades_the_same() {
    // Reversed triangles (inward computed normals) and reversed triangles
    // with outward normals given both give the picture of the original.
    let mesh = capped_cylinder(0.3, 1.2, 64);
    let options = RenderOptions {
        width: 120,
        height: 120,
        views: vec![
            View::front(),
            View {
                elevation_deg: 40.0,
                ..View::back()
            },
        ],
        ..RenderOptions::default()
    };
    let original = render_mesh(&mesh, &options).unwrap().image;
    let mut reversed = mesh.clone();
    for t in &mut reversed.triangles {
        t.swap(1, 2);
    }
    let differs = |a: &[u8], b: &[u8]| a.iter().zip(b).filter(|(p, q)| p.abs_diff(**q) > 2).count();
    let inward = render_mesh(&reversed, &options).unwrap().image;
    assert_eq!(differs(&original.pixels, &inward.pixels), 0);
    reversed.normals = Some(trigbody_render::area_weighted_normals(&mesh));
    let given = render_mesh(&reversed, &options).unwrap().image;
    assert_eq!(differs(&original.pixels, &given.pixels), 0);
}

#[test]
fn sphere_silhouette_is_a_disc() {
    let centre = Vec3::new(0.2, -0.1, 0.3);
    let r = 0.5;
    let mesh = uv_sphere(centre, r, 128, 256);
    for view in [View::front(), View::azimuth(70.0)] {
        let options = measuring(300, view.clone());
        let render = render_mesh(&mesh, &options).unwrap();
        let frame = &render.frames[0];
        let (cx, cy) = frame.project(centre);
        let radius = r * frame.pixels_per_unit;
        let pixels = covered(&render, 0, options.background);
        let expected = std::f64::consts::PI * radius * radius;
        let error = (pixels.len() as f64 - expected) / expected;
        println!(
            "sphere {view}: {} px, disc of radius {radius:.1} px = {expected:.0} px, error {:+.3} %",
            pixels.len(),
            error * 100.0
        );
        assert!(error.abs() < 0.01, "{view}: {error}");
        // The shape, not just the area: covered pixels lie within the disc
        // and every pixel well inside is covered.
        let inside = |x: u32, y: u32| {
            let (dx, dy) = (x as f64 + 0.5 - cx, y as f64 + 0.5 - cy);
            (dx * dx + dy * dy).sqrt()
        };
        assert!(pixels.iter().all(|&(x, y)| inside(x, y) <= radius + 0.5));
        let set: std::collections::HashSet<_> = pixels.into_iter().collect();
        for y in 0..300 {
            for x in 0..300 {
                if inside(x, y) < radius - 1.0 {
                    assert!(set.contains(&(x, y)), "hole at {x},{y}");
                }
            }
        }
    }
}

#[test]
fn views_sit_side_by_side_at_one_scale() {
    let mesh = capped_cylinder(0.2, 1.0, 64);
    let options = RenderOptions {
        width: 120,
        height: 160,
        ..RenderOptions::default()
    };
    let render = render_mesh(&mesh, &options).unwrap();
    assert_eq!((render.image.width, render.image.height), (360, 160));
    assert_eq!(render.frames.len(), 3);
    let lefts: Vec<u32> = render.frames.iter().map(|f| f.left).collect();
    assert_eq!(lefts, vec![0, 120, 240]);
    let k = render.frames[0].pixels_per_unit;
    assert!(render.frames.iter().all(|f| f.pixels_per_unit == k));
}

#[test]
fn rendering_is_deterministic_and_translation_invariant() {
    let mesh = torus(1.0, 0.3, 60, 30);
    let options = RenderOptions {
        width: 200,
        height: 200,
        views: vec![View {
            elevation_deg: 35.0,
            ..View::azimuth(20.0)
        }],
        ..RenderOptions::default()
    };
    let a = render_mesh(&mesh, &options).unwrap();
    let b = render_mesh(&mesh, &options).unwrap();
    assert_eq!(a.image, b.image);
    // Far from the origin the picture is the same up to rounding at a few
    // edge samples.
    let mut moved = mesh.clone();
    for p in &mut moved.positions {
        *p += Vec3::new(1000.0, -2000.0, 500.0);
    }
    let c = render_mesh(&moved, &options).unwrap();
    let differing = a
        .image
        .pixels
        .chunks(3)
        .zip(c.image.pixels.chunks(3))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(u, v)| u.abs_diff(*v) > 8))
        .count();
    assert!(differing < 200, "{differing} pixels differ");
}

#[test]
fn picture_does_not_depend_on_the_thread_count() {
    let mesh = torus(1.0, 0.4, 200, 100);
    let options = RenderOptions {
        width: 256,
        height: 192,
        views: vec![
            View::front(),
            View {
                elevation_deg: 60.0,
                ..View::side()
            },
        ],
        ..RenderOptions::default()
    };
    let with_threads = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        pool.install(|| render_mesh(&mesh, &options).unwrap().image)
    };
    let one = with_threads(1);
    assert_eq!(one, with_threads(3));
    assert_eq!(one, with_threads(8));
}

#[test]
fn supersampled_edges_blend_and_keep_the_coverage() {
    // With 2×2 samples an edge pixel mixes surface and background; the
    // summed coverage (1 − distance to the background colour, by channel)
    // still matches the rectangle.
    let (r, h) = (0.3, 1.2);
    let mesh = capped_cylinder(r, h, 256);
    let options = RenderOptions {
        supersample: 2,
        background: [0, 0, 0],
        ambient: 1.0,
        diffuse: 0.0,
        specular: 0.0,
        color: [255, 255, 255],
        ..measuring(301, View::front())
    };
    let render = render_mesh(&mesh, &options).unwrap();
    let frame = &render.frames[0];
    let mut coverage = 0.0;
    let mut partial = 0;
    for y in 0..301 {
        for x in 0..301 {
            // A white surface over black: the grey level's linear value is
            // the covered fraction of the pixel.
            let v = render.image.pixel(x, y).unwrap()[0];
            let s = v as f64 / 255.0;
            let lin = if s <= 0.04045 {
                s / 12.92
            } else {
                ((s + 0.055) / 1.055).powf(2.4)
            };
            coverage += lin;
            if v != 0 && v != 255 {
                partial += 1;
            }
        }
    }
    let expected = 2.0 * r * h * frame.pixels_per_unit.powi(2);
    let error = (coverage - expected) / expected;
    println!("supersampled cylinder: coverage {coverage:.1} px vs {expected:.1} px ({:+.3} %), {partial} edge pixels", error * 100.0);
    assert!(error.abs() < 0.005, "{error}");
    assert!(partial > 100, "edges are antialiased: {partial}");
}

#[test]
fn tiny_images_do_not_panic() {
    let mesh = uv_sphere(Vec3::ZERO, 1.0, 8, 16);
    let values: Vec<f64> = mesh.positions.iter().map(|p| p.x).collect();
    let field = VertexValues::new(&values, (-1.0, 1.0), "a rather long title (mm)");
    for (w, h) in [(1, 1), (1, 40), (40, 1), (3, 3), (17, 9)] {
        for supersample in [1, 2, 4] {
            let options = RenderOptions {
                width: w,
                height: h,
                supersample,
                ..RenderOptions::default()
            };
            let plain = render_mesh(&mesh, &options).unwrap();
            assert_eq!(plain.image.pixels.len(), 3 * 3 * (w * h) as usize);
            render_mesh_values(&mesh, &field, &options).unwrap();
        }
    }
}

#[test]
fn colour_by_value_with_a_colour_bar() {
    let mesh = uv_sphere(Vec3::ZERO, 1.0, 48, 96);
    // Height above the equator in mm on a 1 m sphere: −1000 … 1000.
    let values: Vec<f64> = mesh.positions.iter().map(|p| p.y * 1000.0).collect();
    let field = VertexValues::new(&values, (-1000.0, 1000.0), "height (mm)");
    let options = RenderOptions {
        width: 300,
        height: 300,
        views: vec![View::front(), View::side()],
        ..RenderOptions::default()
    };
    let render = render_mesh_values(&mesh, &field, &options).unwrap();
    save(&render, "trigbody_render_values.png");
    // Two panels and a colour bar.
    assert!(render.image.width > 600);
    let frame = &render.frames[0];
    let at = |p: Vec3| {
        let (x, y) = frame.project(p);
        render.image.pixel(x as u32, y as u32).unwrap()
    };
    // Near the top the surface is yellow (viridis' high end), near the
    // bottom violet: red and green high at the top, blue over red at the
    // bottom.
    let top = at(Vec3::new(-0.1, 0.85, 0.5));
    let bottom = at(Vec3::new(-0.1, -0.85, 0.5));
    assert!(top[1] > 150 && top[2] < 120, "top {top:?}");
    assert!(bottom[2] > bottom[1], "bottom {bottom:?}");
    // The bar: the top of its gradient is lighter than the bottom.
    // The gradient starts 12 % into the strip and is 14 % of it wide.
    let strip = render.image.width - 600;
    let bar_x = 600 + strip * 19 / 100;
    let bar_top = render.image.pixel(bar_x, (300.0 * 0.15) as u32).unwrap();
    let bar_bottom = render.image.pixel(bar_x, (300.0 * 0.85) as u32).unwrap();
    assert!(luminance(bar_top) > 4.0 * luminance(bar_bottom));
    // Counting errors.
    assert!(matches!(
        render_mesh_values(
            &mesh,
            &VertexValues::new(&values[1..], (0.0, 1.0), "mm"),
            &options
        ),
        Err(RenderError::ValueCount { .. })
    ));
    for range in [(1.0, 1.0), (2.0, 1.0), (f64::NAN, 1.0)] {
        assert!(matches!(
            render_mesh_values(&mesh, &VertexValues::new(&values, range, "mm"), &options),
            Err(RenderError::BadRange { .. })
        ));
    }
}

#[test]
fn missing_values_are_grey() {
    let mesh = uv_sphere(Vec3::ZERO, 1.0, 16, 32);
    let values = vec![f64::NAN; mesh.positions.len()];
    let field = VertexValues::new(&values, (0.0, 10.0), "distance (mm)");
    let options = measuring(100, View::front());
    let render = render_mesh_values(&mesh, &field, &options).unwrap();
    let [r, g, b] = render.image.pixel(50, 50).unwrap();
    assert!(r == g && g == b, "{r} {g} {b}");
}

#[test]
fn empty_mesh_is_an_error() {
    let err = render_mesh(&Mesh::default(), &RenderOptions::default()).unwrap_err();
    assert!(matches!(err, RenderError::Mesh(MeshError::NoVertices)));
    assert!(err.to_string().contains("no vertices"), "{err}");
    let no_triangles = Mesh {
        positions: vec![Vec3::ZERO],
        ..Mesh::default()
    };
    assert!(matches!(
        render_mesh(&no_triangles, &RenderOptions::default()),
        Err(RenderError::Mesh(MeshError::NoTriangles))
    ));
}

#[test]
fn nan_positions_are_an_error() {
    let mut mesh = capped_cylinder(1.0, 1.0, 8);
    mesh.positions[3].y = f64::NAN;
    let err = render_mesh(&mesh, &RenderOptions::default()).unwrap_err();
    assert!(matches!(
        err,
        RenderError::Mesh(MeshError::NonFinite { index: 3, .. })
    ));
    assert!(err.to_string().contains("vertex 3"), "{err}");
}

#[test]
fn degenerate_triangles_do_not_panic() {
    let p = Vec3::new;
    // A zero-area triangle (collinear), a repeated vertex, and one real
    // triangle.
    let mesh = Mesh::new(
        vec![p(0., 0., 0.), p(1., 0., 0.), p(2., 0., 0.), p(0., 1., 0.)],
        vec![[0, 1, 2], [0, 0, 1], [1, 1, 1], [0, 1, 3]],
    )
    .unwrap();
    let render = render_mesh(&mesh, &measuring(50, View::front())).unwrap();
    assert!(!covered(&render, 0, [255, 255, 255]).is_empty());
    // Every vertex at one point; and a flat line seen edge-on.
    let point = Mesh::new(vec![p(1., 2., 3.); 3], vec![[0, 1, 2]]).unwrap();
    let render = render_mesh(&point, &RenderOptions::default()).unwrap();
    assert!(covered(&render, 0, [255, 255, 255]).len() < 2000); // labels only
    let edge_on = Mesh::new(
        vec![p(0., 0., 0.), p(1., 0., 0.), p(0., 0., 1.)],
        vec![[0, 1, 2]],
    )
    .unwrap();
    render_mesh(&edge_on, &measuring(64, View::front())).unwrap();
    // Normals that are zero or NaN-free but useless still shade.
    let mut zero_normals = capped_cylinder(1.0, 1.0, 8);
    zero_normals.normals = Some(vec![Vec3::ZERO; zero_normals.positions.len()]);
    render_mesh(&zero_normals, &measuring(64, View::front())).unwrap();
}

#[test]
fn bad_options_are_errors() {
    let mesh = capped_cylinder(1.0, 1.0, 8);
    let with = |f: &dyn Fn(&mut RenderOptions)| {
        let mut o = measuring(32, View::front());
        f(&mut o);
        render_mesh(&mesh, &o)
    };
    assert!(matches!(
        with(&|o| o.width = 0),
        Err(RenderError::EmptyImage {
            width: 0,
            height: 32
        })
    ));
    assert!(matches!(
        with(&|o| o.height = 0),
        Err(RenderError::EmptyImage { .. })
    ));
    assert!(matches!(
        with(&|o| o.views.clear()),
        Err(RenderError::NoViews)
    ));
    assert!(matches!(
        with(&|o| o.up = Vec3::ZERO),
        Err(RenderError::BadAxes { .. })
    ));
    assert!(matches!(
        with(&|o| o.front = o.up * -2.0),
        Err(RenderError::BadAxes { .. })
    ));
    assert!(matches!(
        with(&|o| o.views[0].azimuth_deg = f64::INFINITY),
        Err(RenderError::BadView { .. })
    ));
    assert!(matches!(
        with(&|o| o.supersample = 0),
        Err(RenderError::BadOption {
            name: "supersample",
            ..
        })
    ));
    assert!(matches!(
        with(&|o| o.margin = f64::NAN),
        Err(RenderError::BadOption { name: "margin", .. })
    ));
    assert!(matches!(
        with(&|o| o.light = [0.0; 3]),
        Err(RenderError::BadOption { name: "light", .. })
    ));
    assert!(matches!(
        with(&|o| {
            o.width = 100_000;
            o.height = 100_000
        }),
        Err(RenderError::TooLarge { .. })
    ));
}

#[test]
fn z_up_model_with_custom_front() {
    // The same cylinder standing on z and facing +x renders the same
    // rectangle as the y-up one.
    let mut mesh = capped_cylinder(0.3, 1.2, 128);
    for p in &mut mesh.positions {
        *p = Vec3::new(p.z, -p.x, p.y); // y → z (up), x → -y
    }
    let options = RenderOptions {
        up: Vec3::Z,
        front: Vec3::X,
        ..measuring(200, View::front())
    };
    let render = render_mesh(&mesh, &options).unwrap();
    let f = &render.frames[0];
    assert!((f.screen_up - Vec3::Z).norm() < 1e-12);
    let pixels = covered(&render, 0, options.background);
    let (h_px, w_px) = (1.2 * f.pixels_per_unit, 0.6 * f.pixels_per_unit);
    let error = (pixels.len() as f64 - h_px * w_px) / (h_px * w_px);
    assert!(error.abs() < 0.02, "{error}");
}

/// The MakeHuman male body from the shared data, when it is there.
#[test]
fn male_body_renders_as_a_shaded_body() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/bodies/mh_male.obj");
    if !path.exists() {
        eprintln!("skipped: {} not found", path.display());
        return;
    }
    let mesh = trigbody_io::read_mesh(&path, &trigbody_io::ReadOptions::default()).unwrap();
    let options = RenderOptions {
        width: 512,
        height: 768,
        ..RenderOptions::default()
    };
    let render = render_mesh(&mesh, &options).unwrap();
    save(&render, "trigbody_render_mh_male.png");
    let bounds = mesh.bounds().unwrap();
    // Fit to view: the body's height or its arm span (front view) fills the
    // panel inside the margin, a fraction of the panel's smaller side.
    let k = render.frames[0].pixels_per_unit;
    let height_px = bounds.size().y * k;
    let margin = 2.0 * options.margin * 512.0;
    let fill = (height_px / (768.0 - margin)).max(bounds.size().x * k / (512.0 - margin));
    assert!((fill - 1.0).abs() < 1e-9, "{fill}");
    // A body covers a good part of its bounding rectangle in the front view
    // (arms away from the torso leave gaps), less in the side view.
    let front = covered(&render, 0, options.background).len() as f64;
    let side = covered(&render, 1, options.background).len() as f64;
    let box_front = bounds.size().x * k * height_px;
    println!(
        "male front {front} px ({:.0} % of its box), side {side} px",
        100.0 * front / box_front
    );
    assert!(front > 0.15 * box_front && front < 0.6 * box_front);
    assert!(side < front);
    // Coloured by a value per vertex (here the distance in mm in front of
    // the body's mid-plane, standing in for a model-to-scan distance).
    let mid = bounds.center().z;
    let values: Vec<f64> = mesh
        .positions
        .iter()
        .map(|p| (p.z - mid) * 1000.0)
        .collect();
    let field = VertexValues::new(&values, (-150.0, 150.0), "distance (mm)");
    let render = render_mesh_values(&mesh, &field, &options).unwrap();
    save(&render, "trigbody_render_mh_male_values.png");
    assert_eq!(render.image.width, 3 * 512 + 184);
}
