//! A model's surfaces tessellated together: the parts, the transitions
//! and the cavities of a body or of a model file, one task per piece.

use crate::geom::mesh::Mesh;
use crate::geom::parallel::each_on_cores;
use crate::surface::part::Part;
use crate::surface::tessellate::{tessellate_part, TessellateError, TessellationOptions};
use crate::surface::transition::Transition;

/// One surface of a model.
#[derive(Clone, Copy, Debug)]
pub enum Piece<'a> {
    /// A part's skin, facing out of the part.
    Part(&'a Part),
    /// A transition between two parts.
    Transition(&'a Transition),
    /// A cavity (a pocket of skin inside another part): its part's skin
    /// turned to face into the pocket.
    Cavity(&'a Part),
}

/// Each piece tessellated with `options`, in order, the pieces taken by
/// the cores as they come free (a torso and a transition differ much in
/// cost); or the index of the first piece that failed, and why.
pub fn tessellate_pieces(
    pieces: &[Piece<'_>],
    options: &TessellationOptions,
) -> Result<Vec<Mesh>, (usize, TessellateError)> {
    let meshes = each_on_cores(pieces, |piece| match *piece {
        Piece::Part(p) => tessellate_part(p, options),
        Piece::Transition(t) => Ok(t.tessellate_with(options)),
        Piece::Cavity(p) => tessellate_part(p, options).map(|mut m| {
            m.flip_orientation();
            m
        }),
    });
    meshes
        .into_iter()
        .enumerate()
        .map(|(i, m)| m.map_err(|e| (i, e)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::trig::{Frame, TrigCurve};
    use crate::geom::math::Vec3;
    use crate::surface::part::PartOptions;

    fn tube() -> Part {
        let curves = (0..5)
            .map(|k| {
                let frame = Frame {
                    origin: Vec3::new(0.0, 0.0, 0.05 * k as f64),
                    e1: Vec3::X,
                    e2: Vec3::Y,
                };
                TrigCurve::circle(frame, 0.1, 3)
            })
            .collect();
        Part::new(curves, &PartOptions::default()).unwrap()
    }

    /// Each piece's mesh in order; a cavity's is its part's turned inside out.
    #[test]
    fn a_cavity_is_its_part_turned_inside_out() {
        let part = tube();
        let options = TessellationOptions::default();
        let meshes =
            tessellate_pieces(&[Piece::Part(&part), Piece::Cavity(&part)], &options).unwrap();
        let alone = tessellate_part(&part, &options).unwrap();
        assert_eq!(meshes[0], alone);
        let mut flipped = alone;
        flipped.flip_orientation();
        assert_eq!(meshes[1], flipped);
    }

    /// The error names the first piece that failed.
    #[test]
    fn the_first_failing_piece_is_named() {
        let part = tube();
        let coarse = TessellationOptions {
            around: 2,
            ..TessellationOptions::default()
        };
        let err = tessellate_pieces(&[Piece::Part(&part), Piece::Cavity(&part)], &coarse);
        assert!(matches!(err, Err((0, TessellateError::TooCoarse { .. }))));
    }
}
