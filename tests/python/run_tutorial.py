#!/usr/bin/env python3
"""Runs docs/tutorial.md as a user would: writes each ```yaml file=NAME block, runs each command
of the ```sh blocks in order in a fresh directory (`talus` is the built binary), checks that each
exits 0, that an output block after a command is in what it printed, and that the numbers the
page quotes are the ones the runs give. Exit 0, or 1 with what went wrong.

    run_tutorial.py --talus build/talus --doc docs/tutorial.md [--keep DIR]
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile


def blocks(text):
    """(info, body) of each fenced block, in order."""
    return [(m.group(1).strip(), m.group(2))
            for m in re.finditer(r"^```([^\n]*)\n(.*?)^```", text, re.S | re.M)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--talus", required=True)
    ap.add_argument("--doc", required=True)
    ap.add_argument("--keep", help="run in this directory and keep it")
    args = ap.parse_args()
    talus = os.path.abspath(args.talus)
    text = open(args.doc, encoding="utf-8").read()
    work = args.keep or tempfile.mkdtemp(prefix="talus-tutorial-")
    os.makedirs(work, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    failures = []
    commands = 0
    last = None
    for info, body in blocks(text):
        if info.startswith("yaml file="):
            with open(os.path.join(work, info.split("=", 1)[1]), "w", encoding="utf-8") as f:
                f.write(body)
        elif info == "sh":
            for line in body.splitlines():
                if not line.strip() or line.lstrip().startswith("#"):
                    continue
                command = re.sub(r"^talus ", talus + " ", line)
                last = subprocess.run(command, shell=True, cwd=work, env=env,
                                      capture_output=True, text=True)
                commands += 1
                print(f"$ {line}\n  exit {last.returncode}")
                if last.returncode != 0:
                    failures.append(f"'{line}' exited {last.returncode}:\n{last.stderr[-2000:]}")
        elif info == "" and last is not None:
            # An output block: what the command before it printed.
            expected = body.strip()
            if expected not in last.stdout + last.stderr:
                failures.append(f"the output block after '{last.args}' is not what it printed:\n"
                                f"expected: {expected}\ngot: {last.stderr.strip()[-2000:]}")
    if commands == 0:
        failures.append("the tutorial has no commands: the parser found nothing")

    def quoted(sentence):
        if sentence not in text:
            failures.append(f"the page does not say what the runs give: '{sentence}'")

    try:
        rows = list(csv.DictReader(open(os.path.join(work, "results/footing/timeseries.csv"))))
        ratio = float(rows[-1]["pressure_footing_y"]) / ((2 + math.pi) * 20e3)
        quoted(f"at 6 cm it is {ratio:.2f} (2 + π) c_u")
        # Two-sided: the coarse footing is within 5 % of Prandtl's pressure.
        if not 0.95 < ratio < 1.05:
            failures.append(f"footing: peak pressure {ratio:.3f} (2 + pi) c_u, outside (0.95, 1.05)")
        fos = json.load(open(os.path.join(work, "results/slope-fos/fos.json")))
        quoted(f"It prints the factor with its bracket: {fos['factor_of_safety']:.2f}")
        levels = json.load(open(os.path.join(work, "results/slope-refine/refinement.json")))
        factors = [level["factor_of_safety"] for level in levels["levels"]]
        quoted(f"gives {factors[0]:.2f} at h = 1 m and {factors[1]:.2f} at h = 0.5 m")
        # Converging from above towards Bishop's 1.38: each finer grid lower, none below it.
        if not factors[0] > factors[1] > 1.38:
            failures.append(f"slope: factors {factors} do not fall towards 1.38")
        if not open(os.path.join(work, "footing.png"), "rb").read(8) == b"\x89PNG\r\n\x1a\n":
            failures.append("footing.png is not a PNG")
    except (OSError, KeyError, IndexError, ValueError) as e:
        failures.append(f"a result the page reads is missing: {e!r}")

    for f in failures:
        print("FAIL:", f)
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    print(f"tutorial: {commands} commands, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
