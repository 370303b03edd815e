"""Speed of the Python model: the batched `FrontEnd.run` against a per-clock `step` loop,
the run-length `FrontEnd.run_segments`, and the force path's batched `ForceKernel.run`.

    target/py-venv/bin/python python/benches/frontend.py [clocks]

Stimulus: random pins held 1..40 clocks (bursts, glitches, scale moves), arm high, the
default settings; the force path runs `tooltouch control`'s scenario (13 000 samples).
Prints clocks/s (samples/s) of each way and the time of a 1 M-clock batch.
"""

import sys
import time

import numpy as np

import tooltouch


def stimulus(clocks, seed=15):
    rng = np.random.default_rng(seed)
    held = rng.integers(1, 40, size=clocks)
    pins = rng.integers(0, 64, size=clocks, dtype=np.uint8) | np.uint8(tooltouch.PIN_ARM)
    return np.repeat(pins, held)[:clocks]


def best_of(runs, f):
    best = float("inf")
    for _ in range(runs):
        t = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t)
    return best


def main():
    clocks = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    settings = tooltouch.Settings()
    pins = stimulus(clocks)
    batched = best_of(5, lambda: tooltouch.FrontEnd(settings).run(pins))
    per_call_clocks = min(clocks, 200_000)
    few = [int(p) for p in pins[:per_call_clocks]]

    def loop():
        fe = tooltouch.FrontEnd(settings)
        for p in few:
            fe.step(p)

    per_call = best_of(3, loop)
    print(f"batched FrontEnd.run: {clocks} clocks in {batched:.3f} s = {clocks / batched / 1e6:.1f} M clocks/s")
    print(
        f"per-call FrontEnd.step loop: {per_call_clocks} clocks in {per_call:.3f} s = "
        f"{per_call_clocks / per_call / 1e6:.2f} M clocks/s"
    )
    print(f"batched / per-call: {(clocks / batched) / (per_call_clocks / per_call):.0f}x")

    rng = np.random.default_rng(15)
    seg_pins = rng.integers(0, 64, size=clocks // 20, dtype=np.uint8) | np.uint8(tooltouch.PIN_ARM)
    seg_cycles = rng.integers(1, 40, size=clocks // 20).astype(np.uint32)
    seg_clocks = int(seg_cycles.sum())
    segments = best_of(5, lambda: tooltouch.FrontEnd(settings).run_segments(seg_pins, seg_cycles))
    print(
        f"run-length FrontEnd.run_segments: {seg_clocks} clocks ({len(seg_pins)} segments) in {segments:.3f} s = "
        f"{seg_clocks / segments / 1e6:.1f} M clocks/s"
    )

    force = tooltouch.ForceSettings.control_scenario("pi", "estimated")
    codes, commands = tooltouch.drive_scenario(force, seed=1)
    kernel = best_of(5, lambda: tooltouch.ForceKernel(force).run(codes, commands))
    print(f"batched ForceKernel.run: {len(codes)} samples in {kernel * 1e3:.2f} ms = {len(codes) / kernel / 1e6:.2f} M samples/s")


if __name__ == "__main__":
    main()
