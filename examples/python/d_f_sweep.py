"""A D_f sweep of a cell pair from Python, notebook style (run it as a script
or paste the cells into Jupyter). Each run stays in memory; the figure is
saved to PNG.

    PYTHONPATH=build/python python3 examples/python/d_f_sweep.py [--beats 3] [--out d_f_sweep.png]
"""

# %% set-up
import argparse
import os

import matplotlib
matplotlib.use("Agg")  # a file, no window (delete this line in a notebook)
import matplotlib.pyplot as plt
import numpy as np

import fibrodem

here = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--beats", type=int, default=3, help="beats at 1 Hz; the last one is measured")
parser.add_argument("--out", default="d_f_sweep.png", help="the figure (PNG)")
args = parser.parse_args()

# %% the scene: one colman myocyte and 4 passive fibroblasts (examples/cell_pair_passive.json)
scene = fibrodem.load_scene(os.path.join(here, "..", "cell_pair_passive.json"))
last_beat_ms = 1000.0 * (args.beats - 1)
scene.set("duration_ms", 1000.0 * args.beats)
scene.set("output.traces.from_ms", last_beat_ms)
scene.set("output.biomarkers.from_ms", last_beat_ms)

# %% the sweep: gap-junction conductance myocyte-fibroblast D_f [nS]
D_f_nS = [0.0, 0.5, 1.0, 2.0, 4.0, 8.0]
results = {}
for D_f in D_f_nS:
    results[D_f] = fibrodem.run(scene.set("coupling.D_f_nS", D_f))

# %% the myocyte's last beat against D_f
myocyte = {D_f: r._biomarkers[r._biomarkers["cell"] == 0][-1] for D_f, r in results.items()}
print("D_f_nS  myocyte RMP_mV  APD90_ms  dV/dt_max_mV_per_ms  fibroblast RMP_mV")
for D_f in D_f_nS:
    b = myocyte[D_f]
    fibroblast_rmp = results[D_f].maps["rmp_mV"][1]
    print("%6.1f  %14.2f  %8.1f  %19.1f  %17.2f" % (D_f, b["rmp_mV"], b["apd90_ms"], b["dvdt_max_mV_per_ms"],
                                                    fibroblast_rmp))

# %% the figure: V of the myocyte per D_f, and APD90 and RMP against D_f
figure, (left, right) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
colours = plt.cm.viridis(np.linspace(0, 0.9, len(D_f_nS)))
for colour, D_f in zip(colours, D_f_nS):
    r = results[D_f]
    left.plot(r.t_ms - last_beat_ms, r.trace("V", 0), color=colour, lw=1, label="D_f %g nS" % D_f)
left.set_xlabel("t since the last beat's start (ms)")
left.set_ylabel("myocyte V (mV)")
left.legend(fontsize="small")
right.plot(D_f_nS, [myocyte[D_f]["apd90_ms"] for D_f in D_f_nS], "o-", label="APD90 (ms)")
right.set_xlabel("D_f (nS)")
right.set_ylabel("myocyte APD90 (ms)")
twin = right.twinx()
twin.plot(D_f_nS, [myocyte[D_f]["rmp_mV"] for D_f in D_f_nS], "s--", color="tab:red")
twin.set_ylabel("myocyte RMP (mV)", color="tab:red")
figure.suptitle("cell pair, colman + 4 passive fibroblasts: D_f sweep")
figure.savefig(args.out, dpi=100)
print("figure:", args.out)
