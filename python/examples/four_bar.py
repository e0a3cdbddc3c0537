"""A four-bar from definition to synthesis, as in a notebook: define the
mechanism, assemble it, sweep a cycle, plot the motion, the coupler curve
and its tolerance band, run a batch of designs, and synthesise a design
whose coupler point passes through nine targets.

    python python/examples/four_bar.py [output folder]

writes the figures (PNG) and the animation (HTML) into the folder
(default ``target/loopkin``).
"""

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import loopkin as kin  # noqa: E402
from loopkin import plot, synthesis  # noqa: E402

out = Path(sys.argv[1] if len(sys.argv) > 1 else "target/loopkin")
out.mkdir(parents=True, exist_ok=True)

# 1. Define: the text is what `mechanism! { … }` takes in Rust.
FourBar = kin.compile(
    """
    /// A crank-rocker four-bar with a coupler point P.
    struct FourBar {
        params   { a, b, c, d, p, beta }
        drivers  { phi }
        unknowns { th3, th4 }
        points   {
            A = vec2(0.0, 0.0);
            B = polar(a, phi);
            D = vec2(d, 0.0);
            C = D + polar(c, th4);
            P = B + polar(p, th3 + beta);
        }
        loops    { B + polar(b, th3) == C; }
        sensitivities { a, b, c, d, p, beta }
    }
    """
)
m = FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
print(FourBar.blocks()[0]["method"])

# 2. Assemble: both assemblies at φ = 30°, by mode.
poses = m.assemble_all(phi=math.radians(30))
for pose in poses:
    print(pose)
s = m.analyze(poses[1], rate=20.0)
print(f"at 30°, 20 rad/s: θ3' = {s.qd['th3']:.4f} rad/s, |v_P| = {s.points['P'].speed:.4f} m/s")

# 3. Sweep a whole turn at 600 rev/min, plot it and animate it.
sw = m.sweep("phi", start=poses[1], turn=True, steps=360, rpm=600)
print(sw, "max |a_P| =", f"{sw.point('P').acceleration_magnitude.max():.1f} m/s²")
axes = plot.motion(sw)
axes[0].set_title("FourBar at 600 rev/min")
axes[0].figure.tight_layout()
axes[0].figure.savefig(out / "motion.png", dpi=110)
ax = plot.path(sw, ["B", "C", "P"])
ax.set_title("paths of B, C and the coupler point P")
ax.figure.savefig(out / "paths.png", dpi=110)
sw.write_animation(out / "four_bar.html", links=[("A", "B"), ("B", "C"), ("D", "C"), ("B", "P"), ("C", "P")])
sw.to_csv(out / "four_bar.csv")

# 4. Tolerances: ±0.1 mm on the lengths, ±0.1° on β, worst case, ×20.
dev = sw.deviations("P", {"a": 1e-4, "b": 1e-4, "c": 1e-4, "d": 1e-4, "p": 1e-4, "beta": math.radians(0.1)})
ax = plot.band(sw, "P", dev, magnify=20)
ax.figure.savefig(out / "band.png", dpi=110)
print(f"worst-case deviation of P: {dev.position_worst.max() * 1e3:.3f} mm")

# 5. A batch: 20 000 crank lengths, on every core.
a = np.linspace(0.02, 0.06, 20_000)
res = m.batch({"a": a}, start=poses[1], sweep=dict(driver="phi", turn=True, steps=90, rpm=600), outputs=["P.acceleration"])
peak = np.nanmax(np.linalg.norm(res["P.acceleration"], axis=2), axis=1)
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(a * 1e3, peak)
ax.set_xlabel("crank a (mm)")
ax.set_ylabel("max |a_P| over a turn (m/s²)")
ax.set_title(f"{res.ok.sum()} of {len(a)} designs turn fully")
ax.grid(True, alpha=0.3)
fig.tight_layout()
fig.savefig(out / "batch.png", dpi=110)

# 6. Synthesis: nine targets at prescribed crank angles 40° apart, taken
#    from the coupler curve of another design (b = 0.13, c = 0.09,
#    p = 0.08, β = 0.9, unknown to the solver); vary b, c, p and β from the
#    design above, within bounds.
phis = np.radians(np.arange(0, 360, 40))
hidden = m.replace(b=0.13, c=0.09, p=0.08, beta=0.9)
h0 = hidden.assemble(phi=0.0, modes=poses[1].modes)
targets = np.array([hidden.analyze(hidden.assemble(h0, phi=f, modes=poses[1].modes)).points["P"].position for f in phis])
bounds = {"b": (0.05, 0.25), "c": (0.05, 0.25), "p": (0.0, 0.2), "beta": (-math.pi, math.pi)}
res = synthesis.path(m, "P", targets, phis, vary=["b", "c", "p", "beta"], start=poses[1], bounds=bounds, xtol=1e-15, ftol=1e-15, gtol=1e-15)
print(f"synthesis: E = {res.error:.3e} m² after {res.evaluations} evaluations: {res.design}")
best = res.design
curve = best.sweep("phi", start=res.poses[0], turn=True, steps=360)
fig, ax = plt.subplots(figsize=(6, 6))
ax.plot(sw.point("P").position[:, 0], sw.point("P").position[:, 1], color="0.7", label="start design")
ax.plot(curve.point("P").position[:, 0], curve.point("P").position[:, 1], label="synthesised")
ax.plot(targets[:, 0], targets[:, 1], "x", color="tab:red", label="targets")
ax.set_aspect("equal", adjustable="datalim")
ax.grid(True, alpha=0.3)
ax.legend()
ax.set_title(f"coupler curve through nine targets, E = {res.error:.2e} m²")
ax.set_xlabel("x (m)")
ax.set_ylabel("y (m)")
fig.tight_layout()
fig.savefig(out / "synthesis.png", dpi=110)
print("wrote", ", ".join(sorted(p.name for p in out.iterdir())))
