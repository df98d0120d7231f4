#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Writes the man page vrsph.1 from the CLI's own --help texts (the command and every
subcommand), so that the page and the program cannot disagree. Used by the install step
(CMake) and thus by the Debian package.

usage: make_manpage.py VRSPH OUTPUT"""
import datetime
import os
import re
import subprocess
import sys


def help_text(binary, *args):
    p = subprocess.run([binary, *args, "--help"], capture_output=True, text=True, timeout=60)
    if p.returncode != 0:
        sys.exit(f"make_manpage: {binary} {' '.join(args)} --help failed: {p.stderr.strip()}")
    return p.stdout.replace(binary, "vrsph")  # the usage line names the program, not its build path


def roff(text):
    """Verbatim block: escapes backslashes and leading dots/quotes."""
    out = []
    for line in text.rstrip().splitlines():
        line = line.replace("\\", "\\e")
        if line.startswith((".", "'")):
            line = "\\&" + line
        out.append(line)
    return ".nf\n" + "\n".join(out) + "\n.fi\n"


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: make_manpage.py VRSPH OUTPUT")
    binary, output = sys.argv[1], sys.argv[2]
    if not (os.path.isfile(binary) and os.access(binary, os.X_OK)):
        sys.exit(f"make_manpage: {binary} is not an executable vrsph program")
    version = subprocess.run([binary, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    top = help_text(binary)
    # CLI11 lists subcommands under "Subcommands:" as "  name   description".
    parts = re.split(r"^subcommands:\s*$", top, flags=re.M | re.I)
    block = parts[1] if len(parts) > 1 else ""
    commands = [m.group(1) for m in re.finditer(r"^\s{2}([a-z][a-z-]*)\s", block, re.M)]
    if not commands:
        sys.exit("make_manpage: found no subcommands in the --help text")
    date = datetime.date.today().isoformat()
    page = [f'.TH VRSPH 1 "{date}" "{version}" "User Commands"',
            ".SH NAME", "vrsph \\- particle discretisations of elliptic operators on irregular point clouds",
            ".SH SYNOPSIS", ".B vrsph", "[\\fIOPTIONS\\fR] \\fICOMMAND\\fR [\\fICOMMAND OPTIONS\\fR]",
            ".SH DESCRIPTION", roff(top)]
    for command in commands:
        page += [f".SH COMMAND: {command.upper()}", roff(help_text(binary, command))]
    page += [".SH EXIT STATUS", "0 success, 1 usage, 2 configuration (also: a feature of a part this build "
             "lacks), 3 input, 4 geometry, 5 numerical.",
             ".SH SEE ALSO", "The README, docs/ and CITATION.cff of the vrsph sources.",
             ".SH LICENCE", "BSD-3-Clause."]
    with open(output, "w", encoding="utf-8") as f:
        f.write("\n".join(page) + "\n")


if __name__ == "__main__":
    main()
