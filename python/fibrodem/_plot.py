"""Result.plot(): a quick look with matplotlib (an optional dependency)."""

import numpy as np


def plot_result(result, path=None, variable="V"):
    import matplotlib.pyplot as plt

    figure, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), constrained_layout=True)
    for cell in result.cells(variable):
        top.plot(result.t_ms, result.trace(variable, cell), lw=0.8,
                 label="cell %d (%s)" % (cell, result.cell_types[cell]) if len(result.cell_types) > cell else str(cell))
    top.set_xlabel("t (ms)")
    top.set_ylabel("%s (mV)" % variable if variable == "V" else variable)
    if result.cells(variable):
        top.legend(fontsize="small", loc="upper right")
    top.set_title(result.summary.get("manifest", {}).get("name", "fibrodem run"))

    beats = result._biomarkers
    for cell in np.unique(beats["cell"]):
        rows = beats[beats["cell"] == cell]
        bottom.plot(rows["beat"], rows["apd90_ms"], "o-", ms=3, label="cell %d" % cell)
    bottom.set_xlabel("beat")
    bottom.set_ylabel("APD90 (ms)")
    if len(beats) == 0:
        bottom.text(0.5, 0.5, "no beats measured", ha="center", transform=bottom.transAxes)
    if path is not None:
        figure.savefig(path, dpi=100)
    return figure
