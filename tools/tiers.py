"""The test suite's two tiers, by measurement: read the durations a whole run printed
(``pytest --durations=0``, as ``make tiers`` runs it) and write tests/slow_tests.txt, the
node ids of the slow tier (``make test-all`` runs them, ``make test`` leaves them out;
tests/conftest.py marks them ``slow``).

    python tools/tiers.py DURATIONS.txt [--seconds 2.0]

A test is slow when its setup, call and teardown together took more than ``--seconds``.
Tests whose nature makes them slow (browsers, soaks, Ray, the wheel) are marked
``@pytest.mark.slow`` in their files and need no line here. Prints both tiers' totals.
"""

from __future__ import annotations

import argparse
import re
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "tests" / "slow_tests.txt"
LINE = re.compile(r"^([\d.]+)s (setup|call|teardown)\s+(\S.*)$")


def durations(text: str) -> Counter:
    """Seconds per test node id (setup + call + teardown) from pytest's durations table."""
    total: Counter = Counter()
    for line in text.splitlines():
        found = LINE.match(line.rstrip())
        if found:
            total[found.group(3)] += float(found.group(1))
    return total


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("durations", type=Path, help="the output of pytest --durations=0")
    p.add_argument("--seconds", type=float, default=2.0,
                   help="a test longer than this is slow (default: 2.0)")
    args = p.parse_args(argv)
    total = durations(args.durations.read_text(errors="replace"))
    if not total:
        print(f"{args.durations}: no durations table (run pytest with --durations=0)",
              file=sys.stderr)
        return 2
    slow = sorted(k for k, v in total.items() if v > args.seconds)
    OUT.write_text(
        "# The slow tier: tests whose setup, call and teardown took more than "
        f"{args.seconds:g} s\n# in a whole run on the 2-core CI machine (llvmpipe). Made by "
        "tools/tiers.py (make tiers);\n# tests/conftest.py marks them slow: make test leaves "
        "them out, make test-all runs them.\n" + "".join(f"{k}\n" for k in slow))
    fast = sum(v for k, v in total.items() if v <= args.seconds)
    print(f"slow tier: {len(slow)} tests, {sum(total[k] for k in slow):.0f} s; fast tier: "
          f"{len(total) - len(slow)} tests, {fast:.0f} s (test seconds, all processes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
