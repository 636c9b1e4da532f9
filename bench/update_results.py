#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Put a benchmark's Markdown output into its own section of bench/RESULTS.md.

  bench/update_results.py [--results FILE] [--section NAME] -- COMMAND [ARG...]
  bench/update_results.py [--results FILE] --section NAME --command TEXT < OUTPUT.md

The first form runs COMMAND, shows its output as it comes and, if it succeeds,
writes its standard output; the section's name is then the program's name and
its arguments unless --section gives one. The second form writes standard
input (for the scripts' own --results options). A section is everything
between the lines <!-- begin NAME --> and <!-- end NAME -->; it is replaced
whole, and added at the end of the file when the file has none. Its first
lines say what made it: the command, the date, the commit and the machine
(and, in the first form, its load average before the command ran).
Python's standard library only.
"""
import argparse
import datetime
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_RESULTS = os.path.join(ROOT, "bench", "RESULTS.md")


def shown_path(arg):
    """ARG as the results file shows it: files of the checkout or beside it
    relative to the checkout's root, other files by their name alone."""
    if "/" not in arg or not os.path.exists(arg):
        return arg
    rel = os.path.relpath(os.path.abspath(arg), ROOT)
    if rel.startswith(os.pardir + os.sep + os.pardir):
        return os.path.basename(arg)
    return rel


def section_name(command):
    """The default section name of COMMAND: program and arguments without
    leading dashes (an HTML comment may not contain "--") or folders."""
    words = [os.path.basename(command[0])]
    for arg in command[1:]:
        arg = arg.lstrip("-")
        words.append(os.path.basename(arg) if "/" in arg else arg)
    name = " ".join(w for w in words if w)
    return re.sub(r"-{2,}", "-", re.sub(r"[\s>]+", " ", name)).strip()


def git(*args):
    try:
        out = subprocess.run(["git", "-C", ROOT, *args], capture_output=True, text=True, check=True)
        return out.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def provenance(results, load):
    """Date, commit (changes to RESULTS aside) and machine (with its load
    average if LOAD), in one line."""
    parts = [datetime.date.today().isoformat()]
    commit = git("rev-parse", "--short", "HEAD")
    if commit:
        dirty = git("status", "--porcelain", "--untracked-files=no", "--", ".",
                    ":(exclude)" + os.path.relpath(os.path.abspath(results), ROOT))
        parts.append("commit " + commit + (" with uncommitted changes" if dirty else ""))
    cpu = ""
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), "")
    except OSError:
        pass
    machine = f"{cpu + ', ' if cpu else ''}{os.cpu_count()} CPUs"
    try:
        with open("/proc/meminfo") as f:
            kb = next(int(l.split()[1]) for l in f if l.startswith("MemTotal:"))
        machine += f", {kb / 1048576:.1f} GB RAM"
    except (OSError, StopIteration):
        pass
    parts.append(machine)
    if load:
        parts.append("load average %.2f" % os.getloadavg()[0])
    return "; ".join(parts)


def replace_section(text, name, body):
    """TEXT with section NAME holding BODY (added at the end if absent)."""
    begin, end = f"<!-- begin {name} -->", f"<!-- end {name} -->"
    section = f"{begin}\n{body.rstrip()}\n{end}\n"
    pattern = re.compile(r"^" + re.escape(begin) + r"\n.*?^" + re.escape(end) + r"\n?", re.S | re.M)
    if pattern.search(text):
        return pattern.sub(lambda _: section, text, count=1)
    if begin in text or end in text:
        raise ValueError(f"section '{name}' has only one of its two markers")
    return text.rstrip("\n") + "\n\n" + section if text.strip() else section


def run(command):
    """Runs COMMAND, echoing its standard output; returns (status, output)."""
    lines = []
    with subprocess.Popen(command, stdout=subprocess.PIPE, text=True) as p:
        for line in p.stdout:
            sys.stdout.write(line)
            sys.stdout.flush()
            lines.append(line)
    return p.returncode, "".join(lines)


def main():
    argv = sys.argv[1:]
    command = []
    if "--" in argv:
        i = argv.index("--")
        argv, command = argv[:i], argv[i + 1:]
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 usage=__doc__.split("\n\n")[1].strip())
    ap.add_argument("--results", default=DEFAULT_RESULTS, help="the results file (default bench/RESULTS.md)")
    ap.add_argument("--section", help="the section's name (default: the command's)")
    ap.add_argument("--command", help="with standard input: the command that printed it")
    a = ap.parse_args(argv)
    if command:
        name = a.section or section_name(command)
        shown = " ".join(shown_path(w) for w in command)
        made = provenance(a.results, load=True)
        status, body = run(command)
        if status != 0:
            print(f"update_results.py: '{shown}' failed (status {status}); {a.results} left as it was",
                  file=sys.stderr)
            return status or 1
    else:
        if not a.section or not a.command:
            ap.error("without a COMMAND after --, give --section and --command and the output on standard input")
        name, shown, body = a.section, a.command, sys.stdin.read()
        made = provenance(a.results, load=False)
    if "--" in name or not name.strip():
        ap.error(f"bad section name '{name}' (an HTML comment may not contain '--')")
    if not body.strip():
        print(f"update_results.py: '{shown}' printed nothing; {a.results} left as it was", file=sys.stderr)
        return 1
    head = f"### `{shown}`\n\n{made}\n\n"
    text = ""
    if os.path.exists(a.results):
        with open(a.results, encoding="utf-8") as f:
            text = f.read()
    try:
        text = replace_section(text, name, head + body)
    except ValueError as e:
        print(f"update_results.py: {a.results}: {e}", file=sys.stderr)
        return 1
    tmp = a.results + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, a.results)
    print(f"update_results.py: section '{name}' of {a.results} updated", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
