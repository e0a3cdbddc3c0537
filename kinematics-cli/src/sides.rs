//! Which assembly a dyad's mode is, in the words of a drawing: the side of
//! the line through the dyad's two ends on which its joint lies ("C left
//! of B→D"), found from the point positions alone.
//!
//! A planar dyad of two angles θa, θb closes a triangle: an end E_a, from
//! which link a turns by θa, an end E_b, from which link b turns by θb,
//! and the joint J of the two links. Its two modes are the two mirror
//! images of J across the line E_a E_b. At an assembled pose:
//!
//! - a point that moves when θb alone changes rides on link b; it turns
//!   about E_b, so E_b = r − R⁻¹(∂r/∂θb) with R the quarter turn (likewise
//!   E_a from a point on link a, where the definition names one);
//! - the joint is the point of link b whose distance from E_a (or, where
//!   no point rides on link a, from some point that moves with neither
//!   angle) does not change when the drivers move, the pose reassembled
//!   in the same modes, and whose directions from E_a and from E_b turn
//!   by exactly what θa and θb do (so that a point merely linked to the
//!   dyad by another link is not taken for its end);
//! - the side is the sign of (E_b − E_a) × (J − E_a): left of E_a→E_b
//!   where positive.
//!
//! Each of the three is named by the point of the definition at its
//! position; a dyad whose ends or joint are not named points is not
//! described.

use kinematics_core::closed::Mode;
use kinematics_core::runtime::Model;

/// `J left of E_a→E_b` (or right) for the block of the angle coordinates
/// `[a, b]` at the assembled pose `p` in the modes `modes`; `None` where
/// the points do not tell (a spatial model, unnamed ends, a degenerate
/// triangle).
pub(super) fn side(m: &Model, p: &[f64], modes: &[Mode], [a, b]: [usize; 2]) -> Option<String> {
    if m.point_dimension() != 2 {
        return None;
    }
    let at = |q: &[f64]| -> Option<Vec<[f64; 2]>> {
        let flat = m.point_positions(q).ok()?;
        Some(flat.chunks_exact(2).map(|c| [c[0], c[1]]).collect())
    };
    let r = at(p)?;
    let size = r
        .iter()
        .flat_map(|x| x.iter())
        .fold(0.0f64, |s, v| s.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let h = 1e-6;
    let turned = |j: usize| {
        let mut q = p.to_vec();
        q[j] += h;
        at(&q)
    };
    let (ra, rb) = (turned(a)?, turned(b)?);
    let moves = |x: &[f64; 2], y: &[f64; 2]| (x[0] - y[0]).hypot(x[1] - y[1]) > 1e-6 * h * size;
    let on = |other: &[[f64; 2]], not: &[[f64; 2]]| -> Vec<usize> {
        (0..r.len())
            .filter(|&k| moves(&other[k], &r[k]) && !moves(&not[k], &r[k]))
            .collect()
    };
    let (on_a, on_b) = (on(&ra, &rb), on(&rb, &ra));
    // The centre a point of a link turns about: r − R⁻¹ ∂r/∂θ.
    let centre = |k: usize, rj: &[[f64; 2]]| -> [f64; 2] {
        let (dx, dy) = ((rj[k][0] - r[k][0]) / h, (rj[k][1] - r[k][1]) / h);
        [r[k][0] - dy, r[k][1] + dx]
    };
    let named = |x: [f64; 2]| -> Option<usize> {
        (0..r.len()).find(|&k| (r[k][0] - x[0]).hypot(r[k][1] - x[1]) <= 1e-5 * size)
    };
    let eb = named(centre(*on_b.first()?, &rb))?;
    // The pose with every driver moved a little, in the same modes.
    let moved = {
        let mut q = p.to_vec();
        for v in q.iter_mut().take(m.drivers()) {
            *v += 1e-3;
        }
        let q = m.assemble_in(&q, modes).ok()?;
        (at(&q)?, q)
    };
    let (moved, mq) = moved;
    // x and y a rigid pair whose direction turns as coordinate j does:
    // the two ends of the link that angle j measures.
    let on_link = |x: usize, y: usize, j: usize| {
        let (d0x, d0y) = (r[x][0] - r[y][0], r[x][1] - r[y][1]);
        let (d1x, d1y) = (moved[x][0] - moved[y][0], moved[x][1] - moved[y][1]);
        let (d0, d1) = (d0x.hypot(d0y), d1x.hypot(d1y));
        let turn = (d0x * d1y - d0y * d1x).atan2(d0x * d1x + d0y * d1y);
        let wanted = mq[j] - p[j];
        (d0 - d1).abs() <= 1e-9 * size
            && d0 > 1e-9 * size
            && (turn - wanted).abs() <= 1e-7 * (1.0 + wanted.abs())
    };
    let candidates: Vec<usize> = match on_a.first() {
        Some(&k) => vec![named(centre(k, &ra))?],
        None => (0..r.len())
            .filter(|&k| k != eb && !moves(&ra[k], &r[k]) && !moves(&rb[k], &r[k]))
            .collect(),
    };
    let (ea, j) = candidates.iter().find_map(|&u| {
        on_b.iter()
            .find(|&&x| on_link(x, u, a) && on_link(x, eb, b))
            .map(|&x| (u, x))
    })?;
    let (e, f, g) = (r[ea], r[eb], r[j]);
    let cross = (f[0] - e[0]) * (g[1] - e[1]) - (f[1] - e[1]) * (g[0] - e[0]);
    let length = (f[0] - e[0]).hypot(f[1] - e[1]) * (g[0] - e[0]).hypot(g[1] - e[1]);
    if cross.abs() <= 1e-9 * length {
        return None;
    }
    let names = m.point_names();
    let side = if cross > 0.0 { "left" } else { "right" };
    Some(format!(
        "{} {side} of {}→{}",
        names[j], names[ea], names[eb]
    ))
}
