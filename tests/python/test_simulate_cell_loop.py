"""simulate_cell in a calibration loop: 10,000 calls do not grow memory."""

import os

import fibrodem


def resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def call():
    # A passive fibroblast for 1 ms: the call's overhead, not its integration, dominates.
    return fibrodem.simulate_cell("passive_fibroblast", parameters={"R_GOhm": 5.0}, duration_ms=1.0,
                                  solver={"method": "rush_larsen", "dt_ms": 0.01}, log=["V"], log_every_ms=0.5,
                                  cell_type="fibroblast")


def test_ten_thousand_calls_do_not_grow_memory():
    for _ in range(500):  # warm-up: plugin loaded, allocator pools filled
        call()
    before = resident_bytes()
    for _ in range(10_000):
        logged = call()
    growth = resident_bytes() - before
    # 3 samples per call: a leak of one call's result (~1 kB of arrays and
    # dict) or of one Simulation (> 10 kB) would show as > 10 MB; allocator
    # noise stays under 2 MB.
    assert growth < 2 * 1024 * 1024, "RSS grew %d bytes over 10,000 calls" % growth
    assert len(logged["t_ms"]) == 3 and abs(logged["V"][-1] - logged["V"][0]) < 1.0
