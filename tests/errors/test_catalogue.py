#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs every row of docs/errors.md against the built vrsph: the exit code must be the
documented one (never a signal), and stderr must contain the documented message.

Usage: test_catalogue.py PATH_TO_VRSPH PATH_TO_errors.md FIXTURE_DIR [--report]
--report prints what each row does instead of asserting (to write the catalogue).
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile

ROW = re.compile(r"^\|\s*(\d+)\s*\|(.*?)\|\s*`(.*)`\s*\|\s*(\d+)\s*\|(.*)\|\s*$")
PREFIX = {2: ("configuration error", "resource limit"), 3: ("input error", "I/O error"),
          4: ("geometry error",), 5: ("numerical error",)}


def rows(doc):
    with open(doc, encoding="utf-8") as f:
        for line in f:
            m = ROW.match(line)
            if m:
                yield int(m.group(1)), m.group(2).strip(), m.group(3), int(m.group(4)), m.group(5).strip()


def run(vrsph, command, fixtures, tmp):
    command = command.replace("{fx}", fixtures).replace("{tmp}", tmp)
    stdout = subprocess.PIPE
    if command.endswith(">/dev/full"):
        command = command[: -len(">/dev/full")]
        stdout = open("/dev/full", "w")
    p = subprocess.run([vrsph, *shlex.split(command)], stdout=stdout, stderr=subprocess.PIPE, text=True,
                       errors="replace", timeout=600, stdin=subprocess.DEVNULL)
    return p.returncode, p.stderr


def main():
    vrsph, doc, fixtures = sys.argv[1:4]
    report = "--report" in sys.argv
    failures, count = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        for num, what, command, code, message in rows(doc):
            count += 1
            rc, err = run(vrsph, command, fixtures, tmp)
            first = err.strip().splitlines()[0] if err.strip() else ""
            if report:
                print(f"{num:3d} rc={rc:3d} (want {code}) {first[:160]}")
                continue
            problems = []
            if rc < 0:
                problems.append(f"killed by signal {-rc}")
            elif rc != code:
                problems.append(f"exit {rc}, documented {code}")
            if message not in ("", "—") and message.lower() not in err.lower():
                problems.append(f"message lacks '{message}'")
            if rc == code and code in PREFIX and err.startswith("vrsph:"):
                if not any(err.startswith(f"vrsph: {p}:") for p in PREFIX[code]):
                    problems.append(f"exit {code} with the wrong kind of message")
            if "Traceback" in err:
                problems.append("a Python traceback reached the user")
            if problems:
                failures.append(f"#{num} {what}: `vrsph {command}`: {'; '.join(problems)}\n    stderr: {first[:300]}")
    if report:
        return 0
    if count < 40:
        failures.append(f"the catalogue has only {count} rows (at least 40 expected)")
    for f in failures:
        print("FAIL", f)
    print(f"{count - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
