#!/usr/bin/env python3
"""make_gaze_paths.py: writes the scripted gaze traces of gaze_paths/ (fovsim CSV: t,x,y).

Run by hand after changing it (the build never runs it); the output is committed:
    python3 scripts/make_gaze_paths.py [out_dir]      # default: gaze_paths/ next to scripts/

Every trace is sampled at 120 Hz (except the 1 ms jump of saccade_worst_case.csv), in normalised
display coordinates with the origin top-left, and starts with one '#' line saying what it is.
Random parts use fixed seeds, so the files only change when this script does.
"""
import math
import os
import random
import sys

RATE = 120.0
DT = 1.0 / RATE


def write(out_dir, name, comment, samples):
    path = os.path.join(out_dir, name)
    last = -1.0
    with open(path, "w", newline="\n") as f:
        f.write("# " + comment + "\n")
        f.write("t,x,y\n")
        for t, x, y in samples:
            assert t > last, (name, t, last)
            last = t
            f.write("%.6f,%.6f,%.6f\n" % (t, x, y))
    print("%s: %d samples, %.3f s" % (path, len(samples), samples[-1][0]))


class Jitter:
    """Fixational eye movement: a slow AR(1) drift plus tremor, kept within +-amp of the target."""

    def __init__(self, rng, amp):
        self.rng, self.amp, self.dx, self.dy = rng, amp, 0.0, 0.0

    def __call__(self):
        a, r = 0.9, self.rng
        self.dx = a * self.dx + (1 - a) * r.gauss(0, self.amp * 2)
        self.dy = a * self.dy + (1 - a) * r.gauss(0, self.amp * 2)
        clip = lambda v: max(-self.amp, min(self.amp, v))
        self.dx, self.dy = clip(self.dx), clip(self.dy)
        tremor = self.amp * 0.25
        return clip(self.dx + r.uniform(-tremor, tremor)), clip(self.dy + r.uniform(-tremor, tremor))


def min_jerk(s):
    """Minimum-jerk position profile 0..1: bell-shaped velocity peaking mid-saccade
    (Flash & Hogan 1985), a common stand-in for the saccade velocity profile."""
    s = max(0.0, min(1.0, s))
    return s * s * s * (10 - 15 * s + 6 * s * s)


def saccade_ms(amplitude):
    """Saccade duration from the main sequence, D = 21 ms + 2.2 ms/deg * A (Carpenter 1988),
    with a normalised unit taken as about 40 deg of visual angle; kept within 30..50 ms."""
    return max(30.0, min(50.0, 21.0 + 2.2 * amplitude * 40.0))


def scanpath(fixations, rng, jitter_amp=0.0015):
    """Samples at 120 Hz for [(x, y, duration_s)], joined by main-sequence saccades."""
    jit = Jitter(rng, jitter_amp)
    # Event list: (start time, end time, kind, from, to)
    events, t = [], 0.0
    for i, (x, y, dur) in enumerate(fixations):
        events.append((t, t + dur, "fix", (x, y), (x, y)))
        t += dur
        if i + 1 < len(fixations):
            nx, ny, _ = fixations[i + 1]
            sd = saccade_ms(math.hypot(nx - x, ny - y)) / 1000.0
            events.append((t, t + sd, "sac", (x, y), (nx, ny)))
            t += sd
    end = t
    out, k = [], 0
    while k * DT <= end + 1e-9:
        tk = k * DT
        ev = next(e for e in events if e[0] <= tk < e[1] or e is events[-1])
        t0, t1, kind, a, b = ev
        if kind == "fix":
            dx, dy = jit()
            out.append((tk, a[0] + dx, a[1] + dy))
        else:
            s = min_jerk((tk - t0) / (t1 - t0))
            out.append((tk, a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s))
        k += 1
    return out


def center_fixation(rng):
    jit = Jitter(rng, 0.002)
    out = []
    for k in range(int(5 * RATE) + 1):
        dx, dy = jit()
        out.append((k * DT, 0.5 + dx, 0.5 + dy))
    return out


def fixation_saccade(rng):
    points = [(0.5, 0.5), (0.22, 0.3), (0.75, 0.28), (0.8, 0.72), (0.3, 0.7), (0.55, 0.45), (0.15, 0.55),
              (0.65, 0.6), (0.45, 0.25), (0.5, 0.5)]
    fixations = [(x, y, rng.uniform(0.3, 0.6)) for x, y in points]
    return scanpath(fixations, rng)


def pursuit_circle():
    f, r = 0.25, 0.25
    return [(k * DT, 0.5 + r * math.cos(2 * math.pi * f * k * DT), 0.5 + r * math.sin(2 * math.pi * f * k * DT))
            for k in range(int(8 * RATE) + 1)]


def pursuit_line():
    # 0.1 -> 0.9 in 2 s (0.4 display widths per second), back, twice: 8 s, y fixed.
    x0, x1, leg = 0.1, 0.9, 2.0
    out = []
    for k in range(int(8 * RATE) + 1):
        t = k * DT
        ph = (t % (2 * leg)) / leg
        s = ph if ph <= 1 else 2 - ph
        out.append((t, x0 + (x1 - x0) * s, 0.5))
    return out


def reading(rng):
    # 5 lines of text: fixations of ~250 ms, forward saccades of ~8 % of the width, an occasional
    # short regression, and a return sweep to the start of the next line.
    fixations = []
    for line in range(5):
        y = 0.3 + 0.08 * line
        x = 0.1 + rng.uniform(0.0, 0.03)
        while x < 0.88:
            fixations.append((x, y + rng.uniform(-0.004, 0.004), rng.uniform(0.2, 0.3)))
            if rng.random() < 0.1 and x > 0.2:
                x -= rng.uniform(0.03, 0.05)  # regression
            else:
                x += rng.uniform(0.06, 0.1)
    return scanpath(fixations, rng, jitter_amp=0.001)


def saccade_worst_case():
    out = [(k * DT, 0.02, 0.02) for k in range(int(RATE) + 1)]  # 0 .. 1.000 s, top-left corner
    t_jump = out[-1][0] + 0.001
    out += [(t_jump + k * DT, 0.98, 0.98) for k in range(int(RATE) + 1)]  # 1 ms later, bottom-right
    return out


def demo_tour(rng):
    """The demo's 4.2 s: fixations and saccades across the view, a smooth pursuit arc through the
    periphery, then a fixation back near the centre; every ring border crosses foliage."""
    head = scanpath([(0.5, 0.45, 0.5), (0.2, 0.35, 0.4), (0.78, 0.3, 0.45), (0.3, 0.6, 0.35)], rng)
    t0 = head[-1][0]
    out = list(head)
    # Pursuit: a quarter-circle arc from (0.3, 0.6) sweeping right over 1.2 s (about 0.5 widths/s).
    cx, cy, r = 0.55, 0.6, 0.25
    for k in range(1, int(1.2 * RATE) + 1):
        a = math.pi + (math.pi * 0.75) * k / (1.2 * RATE)
        out.append((t0 + k * DT, cx + r * math.cos(a), cy + 0.6 * r * math.sin(a)))
    t1, x1, y1 = out[-1]
    tail = scanpath([(x1, y1, 0.01), (0.5, 0.5, 4.2 - t1)], rng)
    out += [(t1 + DT + t, x, y) for t, x, y in tail[1:]]
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.normpath(os.path.join(here, "..", "gaze_paths"))
    os.makedirs(out_dir, exist_ok=True)
    write(out_dir, "center_fixation.csv",
          "central fixation, 5 s at 120 Hz: (0.5, 0.5) with fixational jitter within +-0.002",
          center_fixation(random.Random(1)))
    write(out_dir, "fixation_saccade.csv",
          "10 fixations of 300-600 ms joined by 30-50 ms saccades (min-jerk velocity profile), 120 Hz",
          fixation_saccade(random.Random(2)))
    write(out_dir, "pursuit_circle.csv",
          "smooth pursuit on a circle of radius 0.25 around the centre, 0.25 Hz, 8 s at 120 Hz",
          pursuit_circle())
    write(out_dir, "pursuit_line.csv",
          "smooth pursuit along y = 0.5, x 0.1 -> 0.9 -> 0.1 at 0.4/s, twice, 8 s at 120 Hz",
          pursuit_line())
    write(out_dir, "reading.csv",
          "reading: 5 lines of ~250 ms fixations, small forward saccades, a few regressions, "
          "return sweeps, 120 Hz", reading(random.Random(3)))
    write(out_dir, "demo_tour.csv",
          "the demo's trace: 4 fixations joined by saccades, a 1.2 s smooth pursuit arc, a saccade back to "
          "the centre, 4.2 s at 120 Hz", demo_tour(random.Random(4)))
    write(out_dir, "saccade_worst_case.csv",
          "worst case: 1 s at (0.02, 0.02), then (0.98, 0.98) 1 ms later, 1 s there; 120 Hz apart from the jump",
          saccade_worst_case())


if __name__ == "__main__":
    main()
