"""Comparing two contact laws on one impact, in memory (nothing written to disk).

One free impact of the ball on a fixed socket (scene impact-pair) with the default
Lankarani-Nikravesh law and with restitution-matched, both asked for c_r = 0.5. The
restitution actually achieved is the metric first_impact_restitution: restitution-matched
restitutes the 0.5 it is asked for, Lankarani-Nikravesh far more (README "Contact laws"). The
figure is the force-penetration loop of each: the area inside is the energy lost.

    .venv/bin/python examples/compare_laws.py [OUTPUT_DIR]   # default: results/examples
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import rodend

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("results", "examples")
os.makedirs(out, exist_ok=True)

fig, ax = plt.subplots(figsize=(5, 3.5))
achieved = {}
for law in ("lankarani-nikravesh", "restitution-matched"):
    case = rodend.run_case(
        "impact-pair",
        {"contact.law": law, "contact.restitution": 0.5, "impact.outer_body": "fixed",
         "friction.law": "none", "impact.approach_speed": 0.1},
        integrator={"method": "dopri5", "abs_tol": 1e-10, "rel_tol": 1e-10, "max_step": 1e-5},
        time={"end": 1e-3, "sample_interval": 1e-6},
        signals=["penetration", "contact_force"])
    assert case.status == "ok", case.message
    achieved[law] = case.metrics["first_impact_restitution"]
    delta, force = case.signals["penetration"], case.signals["contact_force"]
    inside = delta > 0                                   # the contact itself (negative: apart)
    ax.plot(delta[inside] * 1e6, force[inside], label=f"{law}: e = {achieved[law]:.3f}")
    print(f"{law:22s} achieved restitution {achieved[law]:.4f}, peak force "
          f"{case.metrics['first_impact_peak_force']:.1f} {case.metric_units['first_impact_peak_force']}")

assert abs(achieved["restitution-matched"] - 0.5) < 1e-4
assert achieved["lankarani-nikravesh"] > 0.6
ax.set_xlabel("penetration [µm]")
ax.set_ylabel("normal contact force [N]")
ax.legend(fontsize=8)
ax.grid(alpha=0.3)
fig.tight_layout()
png = os.path.join(out, "contact_laws.png")
fig.savefig(png, dpi=100)
print("figure:", png)
