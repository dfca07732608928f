//! The closed skin (`trigbody_core::closed_skin`) and the region
//! measurements (`trigbody_core::regions`) on the built-in body: the closed
//! skin checked independently (every edge in exactly two triangles, run
//! once each way; one outer shell plus one void per cavity; no
//! intersecting triangle pairs over a box hierarchy; its volume that of
//! the pieces' union measured by rays, within 0.5 %), and the regions'
//! measurement checked on the input against itself and a shifted copy.

use trigbody_core::internals::measure::regions::{region_fit, Region, Regions};
use trigbody_core::internals::surface::closed_skin::{
    check_closed, closed_skin, closed_soup, union_volume, whole_soup_skin,
};
use trigbody_core::internals::surface::local_skin::local_closed_skin;
use trigbody_core::TessellationOptions;
use trigbody_core::{reconstruct, Body, Mesh, ReconstructOptions};
use trigbody_core::{segment, BodyGeometry, LandmarkKind};
use trigbody_io::{read_mesh, ReadOptions};

fn built_in() -> Mesh {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/bodies/mh_male.obj");
    read_mesh(path, &ReadOptions::default()).expect("the built-in body data/bodies/mh_male.obj")
}

/// The built-in body's model and its pieces at `--mesh`'s tessellation.
fn built_in_pieces() -> (Body, Vec<Mesh>) {
    let input = built_in();
    let (model, _) =
        reconstruct(BodyGeometry::Mesh(&input), &ReconstructOptions::default()).expect("model");
    let tess = TessellationOptions {
        target_edge: Some(0.004 * model.height),
        ..TessellationOptions::default()
    };
    let pieces = model.tessellate_pieces(&tess).unwrap();
    (model, pieces)
}

#[test]
fn closed_skin_of_the_built_in_body_is_one_closed_manifold() {
    let (model, pieces) = built_in_pieces();
    let (solids, cavities) = pieces.split_at(pieces.len() - model.cavities.len());
    assert_eq!(
        cavities.len(),
        3,
        "the built-in mesh models its mouth and eye sockets"
    );
    let skin = closed_skin(solids, cavities).expect("closed skin");
    let check = check_closed(&skin);
    println!("{check:?}");
    assert_eq!(check.bad_edges, 0, "{check:?}");
    assert_eq!(check.misoriented_edges, 0, "{check:?}");
    assert_eq!(check.intersecting_pairs, 0, "{check:?}");
    // The outer shell and a void per cavity (the mouth, the sockets).
    assert_eq!(check.components, 1 + cavities.len(), "{check:?}");
    let rays = union_volume(solids, cavities, model.frame.up, 0.001 * model.height);
    let off = check.volume / rays - 1.0;
    println!(
        "volume {} against rays {rays}: {:+.4} %",
        check.volume,
        100.0 * off
    );
    assert!(off.abs() < 0.005, "{off}");
    // Without the cavity the void is gone and the volume grows by its own.
    let filled = closed_skin(solids, &[]).expect("closed skin");
    let filled_check = check_closed(&filled);
    assert_eq!(filled_check.components, 1, "{filled_check:?}");
    assert!(filled_check.volume > check.volume);
}

#[test]
fn local_and_whole_soup_paths_agree_on_the_built_in_body() {
    let (model, pieces) = built_in_pieces();
    let (solids, cavities) = pieces.split_at(pieces.len() - model.cavities.len());
    let (soup, piece) = closed_soup(solids, cavities).expect("soup");
    // The local path must succeed here (no fallback hidden by closed_skin).
    let local = local_closed_skin(&soup, &piece).expect("the local rebuild");
    let whole = whole_soup_skin(&soup).expect("the whole-soup rebuild");
    let (lc, wc) = (check_closed(&local), check_closed(&whole));
    println!("local {lc:?}\nwhole {wc:?}");
    for c in [&lc, &wc] {
        assert_eq!(c.bad_edges, 0, "{c:?}");
        assert_eq!(c.misoriented_edges, 0, "{c:?}");
        assert_eq!(c.intersecting_pairs, 0, "{c:?}");
        assert_eq!(c.components, 1 + cavities.len(), "{c:?}");
    }
    // The same solid: the crossings are exact in both.
    assert!((lc.volume / wc.volume - 1.0).abs() < 1e-9, "{lc:?} {wc:?}");
}

#[test]
fn regions_measure_zero_against_itself_and_a_shift_against_a_copy() {
    let body = built_in();
    let seg = segment(
        BodyGeometry::Mesh(&body),
        &ReconstructOptions::default().segment,
    )
    .expect("segment");
    let regions = Regions::new(&seg);
    let at = |k| seg.landmark(k).unwrap().position;
    assert_eq!(regions.of(at(LandmarkKind::HeadTop)), Region::Head);
    assert_eq!(regions.of(at(LandmarkKind::Crotch)), Region::Rest);
    assert_eq!(regions.of(at(LandmarkKind::LeftHandTip)), Region::Hands);
    assert_eq!(regions.of(at(LandmarkKind::RightToe)), Region::Feet);
    // Against itself: no distance; the normals agree except on the
    // samples that lie on an edge (the sampling's first point in each
    // triangle is the midpoint of an edge), where the nearest triangle may
    // be the neighbour: a coarse mesh's face has neighbours 30° apart.
    let fits = region_fit(&body, &body, &regions, 20_000, 1000.0);
    for f in &fits {
        assert!(f.samples > 100, "{f:?}");
        assert!(f.rms < 1e-9 && f.off_30 < 0.15, "{f:?}");
    }
    // Turned inside out: every normal opposite.
    let mut flipped = body.clone();
    flipped.flip_orientation();
    for f in region_fit(&body, &flipped, &regions, 20_000, 1000.0) {
        assert!(f.off_30 > 0.99 && f.angle_p90 > 150.0, "{f:?}");
    }
    let mut shifted = body.clone();
    for p in &mut shifted.positions {
        *p += seg.frame.up * 0.001;
    }
    for f in region_fit(&body, &shifted, &regions, 20_000, 1000.0) {
        // At most the shift; less where the surface runs along it.
        assert!(
            f.rms > 0.2 && f.rms <= 1.0 + 1e-6 && f.off_30 < 0.15,
            "{f:?}"
        );
    }
}

#[test]
fn the_built_in_body_s_hands_have_their_fingers() {
    // Its fingers and thumbs are apart: five digits a hand, and the hand
    // region within the issue's 2 mm (5.3 mm as mittens; 0.90 measured
    // on the closed skin's pieces, 100 000 samples).
    let input = built_in();
    let opts = ReconstructOptions::default();
    let seg = segment(BodyGeometry::Mesh(&input), &opts.segment).expect("segment");
    let (model, pieces) = built_in_pieces();
    assert_eq!(model.digits.len(), 10);
    let (solids, cavities) = pieces.split_at(pieces.len() - model.cavities.len());
    let skin = closed_skin(solids, cavities).expect("closed skin");
    let fits = region_fit(&input, &skin, &Regions::new(&seg), 50_000, 1000.0);
    let hands = fits
        .iter()
        .find(|f| f.region == Some(Region::Hands))
        .expect("a hands region");
    assert!(hands.rms < 1.5 && hands.off_30 < 0.15, "{hands:?}");
}
