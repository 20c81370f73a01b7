#!/usr/bin/python3
"""Writes tests/data/gaze_events_labelled.csv: a SYNTHETIC 500 Hz gaze trace with its events as
built (column `event`: fixation, saccade, pursuit, lost), for test_gaze_events' agreement test.

It is synthesised, not recorded: the labels are the generator's own segments, so they are exact by
construction (no hand-labelling judgement). What makes it realistic:
  - saccades follow the main sequence: duration 2.2 ms/deg * A + 21 ms (Carpenter 1988), with a
    minimum-jerk position profile (peak velocity 1.875 A / D);
  - smooth pursuit ramps up and down at 400 deg/s^2 (step-ramp pursuit onset accelerations are a
    few hundred deg/s^2) and holds its target speed between, one with a catch-up saccade;
  - fixations drift slowly (a random walk of ~0.3 deg/s) under white tracker noise of 0.03 deg RMS
    per axis (a video eye tracker at 500 Hz; no microsaccades);
  - a blink: 120 ms of samples with confidence 0 and garbage positions.
Positions are angles (deg, x right, y up) mapped to normalised coordinates of the display the test
uses, 1280 x 720 with a 90 deg horizontal field of view, by the exact mapping (tan over focal).

Run: /usr/bin/python3 tests/data/make_gaze_events_labelled.py > tests/data/gaze_events_labelled.csv
"""
import math
import random

RATE = 500.0
W, H, HFOV = 1280, 720, 90.0
NOISE_DEG = 0.03
DRIFT_DEG_S = 0.3
PURSUIT_ACCEL = 400.0

rng = random.Random(32)
F = 0.5 * W / math.tan(math.radians(HFOV / 2))


def to_norm(ax, ay):
    return 0.5 + F * math.tan(math.radians(ax)) / W, 0.5 - F * math.tan(math.radians(ay)) / H


class Eye:
    def __init__(self):
        self.t = 0.0
        self.x = self.y = 0.0
        self.rows = []

    def emit(self, label, noise=True, valid=True):
        if valid:
            nx = rng.gauss(0, NOISE_DEG) if noise else 0.0
            ny = rng.gauss(0, NOISE_DEG) if noise else 0.0
            u, v = to_norm(self.x + nx, self.y + ny)
            self.rows.append((self.t, u, v, 1.0, label))
        else:
            self.rows.append((self.t, rng.uniform(-0.2, 1.2), rng.uniform(-0.2, 1.2), 0.0, label))
        self.t += 1.0 / RATE

    def fixation(self, ms):
        ang = rng.uniform(0, 2 * math.pi)
        for _ in range(int(ms * RATE / 1000)):
            ang += rng.gauss(0, 0.05)
            self.x += DRIFT_DEG_S / RATE * math.cos(ang)
            self.y += DRIFT_DEG_S / RATE * math.sin(ang)
            self.emit("fixation")

    def saccade(self, tx, ty, drift=(0.0, 0.0)):
        """Minimum-jerk from here to (tx, ty), main-sequence duration; `drift` (deg/s) adds the
        pursuit a catch-up saccade rides on."""
        x0, y0 = self.x, self.y
        amp = math.hypot(tx - x0, ty - y0)
        dur = (2.2 * amp + 21.0) / 1000.0
        n = max(1, int(round(dur * RATE)))
        for k in range(1, n + 1):
            s = k / n
            p = 10 * s**3 - 15 * s**4 + 6 * s**5
            self.x = x0 + (tx - x0) * p + drift[0] * k / RATE
            self.y = y0 + (ty - y0) * p + drift[1] * k / RATE
            self.emit("saccade")

    def pursuit(self, speed, dx, dy, ms, catch_up_at_ms=None, catch_up_deg=0.0):
        """Ramps to `speed` deg/s along (dx, dy), holds, ramps down; all labelled pursuit."""
        n = int(ms * RATE / 1000)
        ramp = speed / PURSUIT_ACCEL
        norm = math.hypot(dx, dy)
        ux, uy = dx / norm, dy / norm
        for k in range(n):
            t = k / RATE
            v = min(speed, PURSUIT_ACCEL * t, PURSUIT_ACCEL * (ms / 1000 - t))
            self.x += ux * v / RATE
            self.y += uy * v / RATE
            if catch_up_at_ms is not None and abs(t * 1000 - catch_up_at_ms) < 0.5 / RATE * 1000:
                self.saccade(self.x + ux * catch_up_deg, self.y + uy * catch_up_deg, (ux * v, uy * v))
            self.emit("pursuit")

    def blink(self, ms):
        for _ in range(int(ms * RATE / 1000)):
            self.emit("lost", valid=False)


def main():
    e = Eye()
    e.fixation(450)
    e.saccade(8.0, 2.0)
    e.fixation(300)
    e.pursuit(15.0, -1.0, 0.0, 800, catch_up_at_ms=250, catch_up_deg=2.0)
    e.fixation(350)
    e.blink(120)
    e.fixation(300)
    e.saccade(-6.0, -10.0)
    e.fixation(250)
    e.pursuit(20.0, 1.0, 1.0, 600)
    e.fixation(300)
    e.saccade(e.x + 5.0, e.y)
    e.fixation(400)
    print("t,x,y,confidence,event")
    for t, u, v, c, label in e.rows:
        print(f"{t:.4f},{u:.6f},{v:.6f},{c:g},{label}")


if __name__ == "__main__":
    main()
