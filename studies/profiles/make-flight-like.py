#!/usr/bin/python3
"""Writes studies/profiles/flight-like.csv, the made-up flight-like duty cycle of
studies/wear-evolution-flight.json (docs/inputs.md "A flight-like duty cycle"):

    /usr/bin/python3 studies/profiles/make-flight-like.py

Provenance: invented for rodend, not recorded. It imitates what a flap or aileron actuator sees
over a short flight: small position corrections most of the time (turbulence, trim) and a few
full strokes (take-off and landing settings). Nothing in it is measured; its numbers are
assumptions chosen to be plausible and are stated here:

- 60 s, sampled every 10 ms (100 Hz, 6001 rows), starting and ending at 0 m (the scene's
  initial position, so that repeated duty cycles join without a jump);
- corrections: the sum of 8 sines with frequencies 0.2-2 Hz (log-spaced) and random phases
  (numpy's default_rng, seed 31), scaled to an RMS of 1.5 mm, faded in and out over 1 s;
- two full strokes, at 10 s and at 45 s: from the correction signal to +50 mm in 1 s
  (raised-cosine), hold 0.2 s, to -50 mm in 1 s, hold 0.2 s, back to 0 in 1 s; the ±50 mm of
  studies/wear-evolution.json's synthetic stroke;
- the corrections are suppressed (faded over 0.5 s) while a stroke runs.

The file is written with 9 significant digits (1 nm and better), comment lines first.
"""
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DURATION, DT = 60.0, 0.01
STROKE, STROKE_TIMES = 0.05, (10.0, 45.0)


def raised_cosine(u):
    """S(u) = u - sin(2 pi u) / (2 pi) on [0, 1], 0 before, 1 after."""
    u = np.clip(u, 0.0, 1.0)
    return u - np.sin(2 * np.pi * u) / (2 * np.pi)


def stroke(t, t0):
    """One full stroke from 0 at t0: +STROKE in 1 s, hold, -STROKE in 1 s, hold, 0 in 1 s."""
    x = STROKE * raised_cosine(t - t0)
    x += -2 * STROKE * raised_cosine(t - t0 - 1.2)
    x += STROKE * raised_cosine(t - t0 - 2.4)
    return x


def window(t, start, end, ramp):
    """1 on [start, end], 0 outside, raised-cosine ramps of `ramp` seconds inside the ends."""
    up = raised_cosine((t - start) / ramp)
    down = 1.0 - raised_cosine((t - (end - ramp)) / ramp)
    return up * down


t = np.round(np.arange(0.0, DURATION + DT / 2, DT), 10)
rng = np.random.default_rng(31)
freqs = np.geomspace(0.2, 2.0, 8)
phases = rng.uniform(0.0, 2 * np.pi, freqs.size)
corrections = sum(np.sin(2 * np.pi * f * t + p) for f, p in zip(freqs, phases))
corrections *= 1.5e-3 / np.sqrt(np.mean(corrections**2))
envelope = window(t, 0.0, DURATION, 1.0)
for t0 in STROKE_TIMES:  # quiet while a stroke runs (3.4 s long), with 0.5 s margins
    envelope *= 1.0 - window(t, t0 - 0.5, t0 + 3.9, 0.5)
x = corrections * envelope + sum(stroke(t, t0) for t0 in STROKE_TIMES)
x[0] = x[-1] = 0.0

with open(os.path.join(HERE, "flight-like.csv"), "w", encoding="utf-8") as f:
    f.write("# made-up flight-like duty cycle: small corrections plus two full strokes;\n")
    f.write("# written by studies/profiles/make-flight-like.py (its docstring states every\n")
    f.write("# assumption); not measured data\n")
    f.write("time [s],position [m]\n")
    for ti, xi in zip(t, x):
        f.write(f"{ti:.2f},{xi:.9g}\n")
