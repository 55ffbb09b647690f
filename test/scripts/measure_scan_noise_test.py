#!/usr/bin/env python3
"""Tests of scripts/measure_scan_noise on logs written here in the Mines format, with a known
noise: sigma = 3 mm + 0.2 % of the range, correlated 0.5 between neighbouring rays (an AR(1)
chain along the scan), a robot that stands for 40 scans and drives for 60. The script must give
back the correlation, each bin's sigma and the line through them; and it must refuse an empty
log, one without noise, one without a stand, a line with too few fields and a field that is
not a number."""
import math
import os
import random
import re
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts",
                      "measure_scan_noise")
RAYS = 682
SIGMA_AT_ZERO_M = 0.003
SIGMA_PER_M = 0.002
RHO = 0.5


def true_ranges(k):
    """A room's smooth walls: the range varies slowly along the scan and from scan to scan,
    between about 0.7 and 4.8 m (every bin of the script)."""
    return [2.75 + 2.0 * math.sin(2.0 * math.pi * i / RAYS + 0.01 * k) for i in range(RAYS)]


def write_log(path, standing_scans, moving_scans, seed=7, noise_scale=1.0):
    generator = random.Random(seed)
    with open(path, "w") as log:
        left = right = 0
        for k in range(standing_scans + moving_scans):
            moving = k >= standing_scans
            if moving:
                left += 40
                right += 42
            truth = true_ranges(k if moving else 0)
            chain = 0.0
            millimetres = []
            for i, range_m in enumerate(truth):
                z = generator.gauss(0.0, 1.0)
                chain = z if i == 0 else RHO * chain + math.sqrt(1.0 - RHO * RHO) * z
                noisy = range_m + noise_scale * (SIGMA_AT_ZERO_M + SIGMA_PER_M * range_m) * chain
                millimetres.append(str(int(round(1000.0 * noisy))))
            fields = [str(100000 * k), "0", str(left), str(right)] + ["0"] * 20 + millimetres + ["0"]
            log.write(" ".join(fields) + "\n")


def run(path):
    return subprocess.run([sys.executable, SCRIPT, path], capture_output=True, text=True)


class MeasureScanNoiseTest(unittest.TestCase):
    def test_gives_back_the_noise_it_was_given(self):
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "log.dat")
            write_log(path, standing_scans=40, moving_scans=60)
            result = run(path)
            self.assertEqual(result.returncode, 0, result.stderr)
            text = result.stdout
            rho1, rho2 = map(float, re.search(
                r"neighbouring rays: (-?[0-9.]+) \(lag 1\), (-?[0-9.]+) \(lag 2\)", text).groups())
            self.assertAlmostEqual(rho1, RHO, delta=0.03, msg=text)
            self.assertAlmostEqual(rho2, RHO * RHO, delta=0.03, msg=text)
            rows = re.findall(
                r"\| ([0-9.]+)-([0-9.]+) \| ([0-9.]+|-) \(\d+\) \| ([0-9.]+|-) \(\d+\) \|", text)
            self.assertGreaterEqual(len(rows), 8, text)
            spatial_bins = 0
            for low, high, temporal_mm, spatial_mm in rows:
                # Within 10 % of sigma at the bin's middle (the walls lie within 0.75-4.75 m).
                middle = min(max(0.5 * (float(low) + float(high)), 0.75), 4.75)
                expected_mm = 1000.0 * (SIGMA_AT_ZERO_M + SIGMA_PER_M * middle)
                for estimate in (temporal_mm, spatial_mm):
                    if estimate != "-":
                        self.assertAlmostEqual(float(estimate), expected_mm,
                                               delta=0.1 * expected_mm, msg=text)
                spatial_bins += spatial_mm != "-"
            self.assertGreaterEqual(spatial_bins, 6, text)
            at_zero_mm, percent = map(float, re.search(
                r"sigma = ([0-9.]+) mm \+ ([0-9.]+) % of the range", text).groups())
            self.assertAlmostEqual(at_zero_mm, 1000.0 * SIGMA_AT_ZERO_M, delta=0.5, msg=text)
            self.assertAlmostEqual(percent, 100.0 * SIGMA_PER_M, delta=0.01, msg=text)

    def assert_refused(self, write, message):
        """The script exits with 1 and names the problem on a log `write` makes."""
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "log.dat")
            write(path)
            result = run(path)
            self.assertEqual(result.returncode, 1, result.stdout)
            self.assertIn(message, result.stderr)

    def test_refuses_logs_it_cannot_measure(self):
        def text(content):
            def write(path):
                with open(path, "w") as log:
                    log.write(content)
            return write

        self.assert_refused(lambda path: write_log(path, standing_scans=0, moving_scans=30),
                            "no stand of the robot long enough")
        self.assert_refused(text(""), "holds no scan")
        self.assert_refused(
            lambda path: write_log(path, standing_scans=40, moving_scans=10, noise_scale=0.0),
            "no noise to measure")
        self.assert_refused(text("1 2 3 4 5\n"), "log.dat:1: 5 fields")
        self.assert_refused(text(" ".join(["1"] * 30 + ["x"] + ["1"] * 676) + "\n"),
                            "log.dat:1: not a number")


if __name__ == "__main__":
    unittest.main()
