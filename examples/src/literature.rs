//! Path-generation problems from the literature on four-bar synthesis.

/// Five precision points on a straight line, with the ground pivots at
/// (0, 0) and (1, 0): Problem 7 of A. P. Morgan and C. W. Wampler,
/// "Solving a Planar Four-Bar Design Problem Using Continuation",
/// Journal of Mechanical Design 112 (1990) 544–550, whose polynomial
/// continuation finds every solution, each passing through the points
/// exactly (the best error is zero).
pub const MORGAN_WAMPLER_7: [[f64; 2]; 5] = [
    [0.50, 1.06],
    [-0.83, -0.27],
    [-0.34, 0.22],
    [-0.13, 0.43],
    [0.22, 0.78],
];

/// Nine precision points, the most a four-bar's coupler curve can be
/// made to pass through with all nine dimensions free: the nine-point
/// path synthesis problem, solved completely by C. W. Wampler,
/// A. P. Morgan and A. J. Sommese, "Complete Solution of the Nine-Point
/// Path Synthesis Problem for Four-Bar Linkages", Journal of Mechanical
/// Design 114 (1992) 153–159, whose real solutions pass through the
/// points exactly (the best error is zero). These nine points are the
/// worked example of the HomotopyContinuation.jl nine-point example
/// (P. Breiding, A. Eckhardt, S. Timme, 2019).
pub const NINE_POINTS: [[f64; 2]; 9] = [
    [0.896_186_7, -0.098_029_17],
    [1.215_653_5, -1.187_491_00],
    [1.515_143_5, -0.854_498_08],
    [1.675_477_5, -0.487_680_58],
    [1.713_869_0, -0.300_992_32],
    [1.721_523_6, 0.032_699_53],
    [1.664_202_9, 0.332_410_88],
    [1.498_417_1, 0.744_355_76],
    [1.301_183_4, 0.921_538_06],
];
