//! The links of a mechanism, found from its motion rather than listed: a
//! link is a largest set of points that move rigidly together (every
//! distance between two of them the same at every sample of a sweep),
//! the frame the set of points that do not move. From the links, the
//! pairs of points an animation draws, and for a four-bar (four links in
//! one loop of pin joints) its link lengths, for
//! [`grashof`](crate::merit::grashof).
//!
//! Distances are compared to 1e-9 of the mechanism's size (the largest
//! coordinate of a point over the sweep), over every sample: a sweep of
//! a few samples over a small range can take two points of different
//! links for one link, so sweep a real range (at least three samples
//! that differ).

use alloc::vec::Vec;

use crate::sweep::Table;

/// A link: the points (indices, in declaration order) that move rigidly
/// together, and whether it is the frame (its points do not move).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Link {
    /// Its points.
    pub points: Vec<usize>,
    /// Whether it is the frame.
    pub frame: bool,
}

/// The most points whose links are looked for (the search for the
/// largest rigid sets is exponential in the worst case).
pub const MAX_POINTS: usize = 48;

/// The links of the mechanism swept in `table` (see the module's
/// documentation), the frame first if any point is fixed; every link has
/// at least two points. Empty with fewer than three samples, more than
/// [`MAX_POINTS`] points, or positions that are not finite.
#[must_use]
pub fn links<T: Table + ?Sized>(table: &T) -> Vec<Link> {
    let (n, rows) = (table.point_names().len(), table.rows());
    if rows < 3 || !(2..=MAX_POINTS).contains(&n) {
        return Vec::new();
    }
    let at = |i: usize, k: usize| table.point(i, k)[0];
    let mut size: f64 = 0.0;
    for i in 0..rows {
        for k in 0..n {
            for x in at(i, k) {
                if !x.is_finite() {
                    return Vec::new();
                }
                size = size.max(x.abs());
            }
        }
    }
    let tol = 1e-9 * size.max(f64::MIN_POSITIVE);
    let distance = |i: usize, a: usize, b: usize| {
        crate::math::sqrt(
            at(i, a)
                .iter()
                .zip(at(i, b))
                .map(|(x, y)| (x - y) * (x - y))
                .sum::<f64>(),
        )
    };
    let fixed: Vec<bool> = (0..n)
        .map(|k| {
            (1..rows).all(|i| {
                at(i, k)
                    .iter()
                    .zip(at(0, k))
                    .all(|(x, y)| (x - y).abs() <= tol)
            })
        })
        .collect();
    // Two fixed points are both on the frame; a fixed and a moving point
    // at a constant distance are a link turning about it.
    let rigid: Vec<Vec<bool>> = (0..n)
        .map(|a| {
            (0..n)
                .map(|b| {
                    let d0 = distance(0, a, b);
                    a != b && (1..rows).all(|i| (distance(i, a, b) - d0).abs() <= tol)
                })
                .collect()
        })
        .collect();
    let mut out = Vec::new();
    let frame: Vec<usize> = (0..n).filter(|&k| fixed[k]).collect();
    if frame.len() >= 2 {
        out.push(Link {
            points: frame,
            frame: true,
        });
    }
    // The largest rigid sets with a moving point (Bron–Kerbosch with a
    // pivot), each of two points or more.
    let mut cliques = Vec::new();
    bron_kerbosch(
        &rigid,
        Vec::new(),
        (0..n).collect(),
        Vec::new(),
        &mut cliques,
    );
    cliques.sort();
    for c in cliques {
        if c.len() >= 2 && c.iter().any(|&k| !fixed[k]) {
            out.push(Link {
                points: c,
                frame: false,
            });
        }
    }
    out
}

/// Every largest clique of `adjacent` containing `r`, from the
/// candidates `p`, none of `x` (already reported with it).
fn bron_kerbosch(
    adjacent: &[Vec<bool>],
    r: Vec<usize>,
    mut p: Vec<usize>,
    mut x: Vec<usize>,
    out: &mut Vec<Vec<usize>>,
) {
    if p.is_empty() && x.is_empty() {
        out.push(r);
        return;
    }
    let pivot = p
        .iter()
        .chain(&x)
        .copied()
        .max_by_key(|&u| p.iter().filter(|&&v| adjacent[u][v]).count());
    let Some(pivot) = pivot else {
        return;
    };
    let candidates: Vec<usize> = p.iter().copied().filter(|&v| !adjacent[pivot][v]).collect();
    for v in candidates {
        let mut r2 = r.clone();
        r2.push(v);
        r2.sort_unstable();
        let p2 = p.iter().copied().filter(|&u| adjacent[v][u]).collect();
        let x2 = x.iter().copied().filter(|&u| adjacent[v][u]).collect();
        bron_kerbosch(adjacent, r2, p2, x2, out);
        p.retain(|&u| u != v);
        x.push(v);
    }
}

/// The pairs of points an animation draws for `links`: every pair of
/// points of each moving link (the frame is not drawn).
#[must_use]
pub fn drawn_pairs(links: &[Link]) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    for l in links.iter().filter(|l| !l.frame) {
        for (i, &a) in l.points.iter().enumerate() {
            for &b in &l.points[i + 1..] {
                pairs.push((a, b));
            }
        }
    }
    pairs
}

/// A four-bar's links by their role: each as the two joints it joins.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FourBarLinks {
    /// The frame's two pivots.
    pub ground: [usize; 2],
    /// The link at the first pivot, from the pivot to its pin.
    pub input: [usize; 2],
    /// The coupler, between the two moving pins.
    pub coupler: [usize; 2],
    /// The link at the second pivot, from the pivot to its pin.
    pub output: [usize; 2],
}

impl FourBarLinks {
    /// The lengths (ground, input, coupler, output) at sample `i` of
    /// `table`, in [`grashof`](crate::merit::grashof)'s order.
    ///
    /// # Panics
    /// If `i` is not a sample of `table`.
    #[must_use]
    pub fn lengths<T: Table + ?Sized>(&self, table: &T, i: usize) -> [f64; 4] {
        let d = |[a, b]: [usize; 2]| {
            crate::math::sqrt(
                table.point(i, a)[0]
                    .iter()
                    .zip(table.point(i, b)[0])
                    .map(|(x, y)| (x - y) * (x - y))
                    .sum::<f64>(),
            )
        };
        [
            d(self.ground),
            d(self.input),
            d(self.coupler),
            d(self.output),
        ]
    }
}

/// Where `links` are a four-bar (a frame with two pivots, a link from
/// each pivot to a pin, and a coupler joining the two pins; other points
/// may ride on the links), its links by role: the input is the link
/// whose angular velocity at the first sample equals the swept driver's
/// rate (a crank driven directly); `None` otherwise, and for a spatial
/// mechanism. For the four-bar loops inside a larger linkage, see
/// [`four_bars`].
#[must_use]
pub fn four_bar<T: Table + ?Sized>(table: &T, links: &[Link]) -> Option<FourBarLinks> {
    if links.iter().filter(|l| !l.frame).count() != 3 {
        return None;
    }
    four_bars(table, links).into_iter().next()
}

/// Every four-bar loop of `links` driven by its input crank: two links
/// from distinct frame pivots (one of them turning at the swept driver's
/// rate at the first sample, the input), joined through their pins by a
/// coupler link that touches the frame nowhere. A Stephenson III six-bar
/// has one (the loop its dyad hangs from); a four-bar is one. Planar
/// mechanisms only (empty for a spatial one).
#[must_use]
pub fn four_bars<T: Table + ?Sized>(table: &T, links: &[Link]) -> Vec<FourBarLinks> {
    let mut found = Vec::new();
    if table.point_dim() != 2 || table.rows() == 0 {
        return found;
    }
    let Some(frame) = links.iter().find(|l| l.frame) else {
        return found;
    };
    let shared = |a: &Link, b: &Link| -> Vec<usize> {
        a.points
            .iter()
            .copied()
            .filter(|p| b.points.contains(p))
            .collect()
    };
    // Side links share one pivot with the frame; couplers none.
    let mut sides = Vec::new();
    let mut couplers = Vec::new();
    for l in links.iter().filter(|l| !l.frame) {
        match shared(l, frame).as_slice() {
            [pivot] => sides.push((l, *pivot)),
            [] => couplers.push(l),
            _ => {}
        }
    }
    let omega = |[pivot, pin]: [usize; 2]| {
        let ([r0, v0, _], [r1, v1, _]) = (table.point(0, pivot), table.point(0, pin));
        let (dx, dy) = (r1[0] - r0[0], r1[1] - r0[1]);
        let (vx, vy) = (v1[0] - v0[0], v1[1] - v0[1]);
        (dx * vy - dy * vx) / (dx * dx + dy * dy)
    };
    let Some(driver) = table
        .coordinates()
        .iter()
        .position(|c| c.name == table.variable())
    else {
        return found;
    };
    let rate = table.coordinate(0, driver, 1);
    let driven = |side: [usize; 2]| (omega(side) - rate).abs() <= 1e-9 * rate.abs().max(1e-300);
    for (i, &(a, pa)) in sides.iter().enumerate() {
        for &(b, pb) in &sides[i + 1..] {
            if pa == pb {
                continue;
            }
            for &coupler in &couplers {
                let (ja, jb) = match (shared(a, coupler).as_slice(), shared(b, coupler).as_slice())
                {
                    ([ja], [jb]) if ja != jb => (*ja, *jb),
                    _ => continue,
                };
                let (first, second) = if driven([pa, ja]) {
                    ([pa, ja], [pb, jb])
                } else if driven([pb, jb]) {
                    ([pb, jb], [pa, ja])
                } else {
                    continue;
                };
                found.push(FourBarLinks {
                    ground: [first[0], second[0]],
                    input: first,
                    coupler: [first[1], second[1]],
                    output: second,
                });
            }
        }
    }
    found
}
