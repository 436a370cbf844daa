#!/usr/bin/env python3
"""How long a Python call takes to answer Ctrl-C at a million faces (issue 57, item 7).

    PYTHONPATH=build/python /usr/bin/python3 scripts/ctrl_c_probe.py lbo|cmds|geodesics [DELAY...]

Generates the icosphere of 8 subdivisions (655,362 vertices, 1,310,720 faces), starts the call, sends the
process SIGINT after each DELAY seconds (one run per delay; default 1 2 4 6 9 12) and prints the time from the
signal to KeyboardInterrupt. geodesics: the heat method from 2,000 sources. A call that ends before its signal
says so. tests/python/test_ctrl_c.py checks the same bound on small meshes.
"""
import os
import signal
import subprocess
import sys
import time


def one_run(what, delay):
    import threading

    import cshapes

    V, F = cshapes.generate("icosphere", subdivisions=8)
    sent = {}

    def fire():
        time.sleep(delay)
        sent["t"] = time.time()
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=fire, daemon=True).start()
    start = time.time()
    try:
        if what == "geodesics":
            cshapes.geodesics(V, F, sources=list(range(2000)))
        else:
            cshapes.canonical_form(V, F, method=what)
        print(f"{what}: finished before the signal, in {time.time() - start:.1f} s")
    except KeyboardInterrupt:
        print(f"{what}: signal at {delay:g} s, KeyboardInterrupt {time.time() - sent['t']:.2f} s after it")


def main():
    if len(sys.argv) < 2 or sys.argv[1] not in ("lbo", "cmds", "geodesics"):
        sys.exit(__doc__)
    if len(sys.argv) == 4 and sys.argv[2] == "--one":
        one_run(sys.argv[1], float(sys.argv[3]))
        return
    for delay in (sys.argv[2:] or ["1", "2", "4", "6", "9", "12"]):
        subprocess.run([sys.executable, __file__, sys.argv[1], "--one", delay], check=False)


if __name__ == "__main__":
    main()
