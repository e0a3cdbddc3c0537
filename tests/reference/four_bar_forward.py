#!/usr/bin/env python3
"""Independent high-precision reference: forward dynamics of a planar four-bar
(crank-rocker) driven by a DC motor, with gravity and a spring-damper.

Derivation: closed-form position analysis (circle-circle intersection, branch
with C to the left of B->D, i.e. above the x axis at phi = 0), all derivatives
obtained by exact symbolic differentiation (sympy), Lagrange equation in the
single coordinate phi:
    M(phi) phi'' + 1/2 M'(phi) phi'^2 + V'(phi) = Q
Integration: fixed-step Gauss-Legendre implicit Runge-Kutta (s stages, order
2s) in mpmath, stage equations solved by fixed-point iteration to 1e-(dps-5).
Convergence: run with two step sizes (h and h/2) and two precisions and
compare.  The motor work and the damper work are integrated alongside the
state for an energy-balance self-check.
"""
import sys
import time
import sympy as sp
import mpmath as mp

# ---------------------------------------------------------------- data (exact)
R = sp.Rational
a, b, c, d = R(4, 100), R(12, 100), R(10, 100), R(11, 100)
m2, m3, m4 = R(3, 10), R(5, 10), R(4, 10)
J2, J3, J4 = R(20, 10000), R(6, 10000), R(35, 100000)
g = R(981, 100)
Ts, w0 = R(1, 2), R(60)
k, L0, cdamp = R(50), R(1, 10), R(2)
P0 = (R(5, 100), R(15, 100))

# ---------------------------------------------------------------- kinematics
phi = sp.Symbol('phi', real=True)
Bx, By = a * sp.cos(phi), a * sp.sin(phi)
ex, ey = d - Bx, -By                       # vector B -> D
L2 = ex**2 + ey**2
p = (b**2 - c**2 + L2) / (2 * L2)           # along e (fraction of |e|)
q = sp.sqrt(b**2 / L2 - p**2)               # along perp(e) = (-ey, ex): left side
Cx = Bx + p * ex - q * ey
Cy = By + p * ey + q * ex
th3 = sp.atan2(Cy - By, Cx - Bx)
th4 = sp.atan2(Cy, Cx - d)

G2 = (Bx / 2, By / 2)
G3 = ((Bx + Cx) / 2, (By + Cy) / 2)
G4 = ((d + Cx) / 2, Cy / 2)

def D(e):
    return sp.diff(e, phi)

th3p, th4p = D(th3), D(th4)
M = (m2 * (D(G2[0])**2 + D(G2[1])**2) + J2
     + m3 * (D(G3[0])**2 + D(G3[1])**2) + J3 * th3p**2
     + m4 * (D(G4[0])**2 + D(G4[1])**2) + J4 * th4p**2)
Lspr = sp.sqrt((G3[0] - P0[0])**2 + (G3[1] - P0[1])**2)
V = g * (m2 * G2[1] + m3 * G3[1] + m4 * G4[1]) + k / 2 * (Lspr - L0)**2
Mp, Vp, Lp = D(M), D(V), D(Lspr)

names = ['Bx', 'By', 'Cx', 'Cy', 'th3', 'th4', 'th3p', 'th4p', 'M', 'Mp', 'V', 'Vp', 'L', 'Lp']
exprs = [Bx, By, Cx, Cy, th3, th4, th3p, th4p, M, Mp, V, Vp, Lspr, Lp]
F_all = sp.lambdify(phi, exprs, modules='mpmath', cse=True)
F_dyn = sp.lambdify(phi, [M, Mp, Vp, Lp], modules='mpmath', cse=True)

def kin(x):
    return dict(zip(names, F_all(x)))

# ---------------------------------------------------------------- ODE
def rhs(t, y):
    ph, w = y[0], y[1]
    Mv, Mpv, Vpv, Lpv = F_dyn(ph)
    Ldot = Lpv * w
    Tm = Ts * (1 - w / w0)
    Q = Tm - cdamp * Ldot * Lpv
    acc = (Q - Mpv * w * w / 2 - Vpv) / Mv
    return [w, acc, Tm * w, -cdamp * Ldot * Ldot]   # phi, phidot, W_motor, W_damper

def gauss_legendre_tableau(s):
    # nodes: roots of shifted Legendre P_s(2x-1); A_ij = int_0^{c_i} l_j
    x = sp.Symbol('x')
    P = sp.legendre(s, 2 * x - 1)
    roots = sorted(mp.polyroots([mp.mpf(sp.Poly(P, x).coeff_monomial(x**n)) for n in range(s, -1, -1)],
                                maxsteps=500, extraprec=4 * mp.mp.prec))
    cs = [mp.re(r) for r in roots]
    A = [[None] * s for _ in range(s)]
    bw = [None] * s
    for j in range(s):
        # Lagrange basis polynomial l_j as mpmath coefficient list
        def lj(t, j=j):
            v = mp.mpf(1)
            for m_ in range(s):
                if m_ != j:
                    v *= (t - cs[m_]) / (cs[j] - cs[m_])
            return v
        bw[j] = mp.quad(lj, [0, 1])
        for i in range(s):
            A[i][j] = mp.quad(lj, [0, cs[i]])
    return cs, A, bw

def integrate(t_out, nsub, s):
    """Fixed-step Gauss-Legendre; nsub steps between consecutive outputs."""
    cs, A, bw = gauss_legendre_tableau(s)
    tol = mp.mpf(10) ** (-(mp.mp.dps - 5))
    y = [mp.mpf(0), mp.mpf(0), mp.mpf(0), mp.mpf(0)]
    t = mp.mpf(0)
    out = []
    tprev = mp.mpf(0)
    nev = 0
    for to in t_out:
        to = mp.mpf(to)
        h = (to - tprev) / nsub
        for _ in range(nsub):
            f0 = rhs(t, y); nev += 1
            K = [list(f0) for _ in range(s)]
            for it in range(200):
                Knew = []
                for i in range(s):
                    yi = [y[n] + h * mp.fsum(A[i][j] * K[j][n] for j in range(s)) for n in range(4)]
                    Knew.append(rhs(t + cs[i] * h, yi)); nev += 1
                err = max(abs(Knew[i][n] - K[i][n]) * h for i in range(s) for n in range(4))
                K = Knew
                if err < tol:
                    break
            else:
                raise RuntimeError('fixed point did not converge')
            y = [y[n] + h * mp.fsum(bw[j] * K[j][n] for j in range(s)) for n in range(4)]
            t += h
        tprev = to
        out.append((to, list(y)))
    return out, nev

# ---------------------------------------------------------------- checks
def loop_closure_check():
    worst = mp.mpf(0)
    for x in ['0', '0.7', '1.9', '3.14159', '4.4', '5.9', '37.3']:
        x = mp.mpf(x)
        K = kin(x)
        rx = K['Bx'] + b * mp.cos(K['th3']) - d - c * mp.cos(K['th4'])
        ry = K['By'] + b * mp.sin(K['th3']) - c * mp.sin(K['th4'])
        # implicit differentiation cross-check of th3', th4':
        #  -b sin3 th3' + c sin4 th4' = a sin(phi);  b cos3 th3' - c cos4 th4' = -a cos(phi)
        Mx = mp.matrix([[-b * mp.sin(K['th3']), c * mp.sin(K['th4'])],
                        [b * mp.cos(K['th3']), -c * mp.cos(K['th4'])]])
        sol = mp.lu_solve(Mx, mp.matrix([a * mp.sin(x), -a * mp.cos(x)]))
        dd = max(abs(sol[0] - K['th3p']), abs(sol[1] - K['th4p']))
        worst = max(worst, abs(rx), abs(ry))
        print('  phi=%-8s closure |r|=(%s, %s)  th4=%s  |dth(sym)-dth(implicit)|=%s'
              % (mp.nstr(x, 6), mp.nstr(abs(rx), 3), mp.nstr(abs(ry), 3), mp.nstr(K['th4'], 8), mp.nstr(dd, 3)))
    return worst

def fmt(x):
    return mp.nstr(x, 17, strip_zeros=False)

def table(out):
    rows = []
    for t, y in out:
        K = kin(y[0])
        KE = K['M'] * y[1]**2 / 2
        rows.append((t, y[0], y[1], K['th3'], K['th4'], KE, K['V'], y[2], y[3]))
    return rows

if __name__ == '__main__':
    dps = int(sys.argv[1]) if len(sys.argv) > 1 else 34
    nsub = int(sys.argv[2]) if len(sys.argv) > 2 else 400
    s = int(sys.argv[3]) if len(sys.argv) > 3 else 6
    outfile = sys.argv[4] if len(sys.argv) > 4 else 'four_bar_forward.txt'
    mp.mp.dps = dps
    print('dps=%d, Gauss-Legendre s=%d (order %d), h=%s' % (dps, s, 2 * s, mp.nstr(mp.mpf(0.25) / nsub, 6)))
    print('loop closure / derivative checks:')
    wc = loop_closure_check()
    print('  worst closure residual: %s' % mp.nstr(wc, 3))
    t0 = time.time()
    ts = ['0.25', '0.5', '0.75', '1.0', '1.25', '1.5', '1.75', '2.0']
    out, nev = integrate(ts, nsub, s)
    print('integration: %d rhs evals, %.1f s' % (nev, time.time() - t0))
    rows = table(out)
    E0 = kin(mp.mpf(0))['V']
    with open(outfile, 'w') as fh:
        fh.write('# t phi phidot th3 th4 kinetic_energy\n')
        for r in rows:
            fh.write(' '.join(fmt(v) for v in r[:6]) + '\n')
    for r in rows:
        print(' '.join(fmt(v) for v in r[:6]))
    t, ph, w, t3, t4, KE, Vv, Wm, Wd = rows[-1]
    bal = KE + Vv - Wm - Wd
    print('energy balance at t=2: T=%s V=%s W_motor=%s W_damper=%s' % tuple(fmt(v) for v in (KE, Vv, Wm, Wd)))
    print('  T+V-Wm-Wd = %s ; at t=0: %s ; difference %s' % (fmt(bal), fmt(E0), mp.nstr(bal - E0, 5)))
