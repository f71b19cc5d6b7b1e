"""docs/commands.md against the command: every flag that a subcommand's
--help lists must appear, in backticks, in that subcommand's section of the
page (the lines from its `## plausible NAME` heading to the next `## `).
--help itself is left out. Fails naming each missing flag and its subcommand,
and each --help that does not state the exit codes (issue 56: help that tells
the truth).
Usage: commands_doc_test.py PLAUSIBLE DOCS_COMMANDS_MD
"""
import re
import subprocess
import sys

SUBCOMMANDS = ("list", "run", "render", "check", "report", "video", "view")


def help_of(exe, cmd):
    return subprocess.run([exe, cmd, "--help"], capture_output=True, text=True, check=True).stdout


EXIT_CODES = ("Exit codes: 0 ", "; 1 ", "; 2 bad input", "130 or 143")


def flags_of(out):
    options = out.split("Options:", 1)[1] if "Options:" in out else ""
    # An option line starts with spaces, then -x, or --name (CLI11's layout).
    found = []
    for line in options.splitlines():
        m = re.match(r"\s+(?:-\w,)?(--[A-Za-z0-9][A-Za-z0-9-]*)", line)
        if m and m.group(1) != "--help" and m.group(1) not in found:
            found.append(m.group(1))
    return found


def sections_of(page):
    sections, name = {}, None
    for line in page.splitlines():
        m = re.match(r"## plausible (\w+)", line)
        if m:
            name = m.group(1)
            sections[name] = ""
        elif line.startswith("## "):
            name = None
        elif name:
            sections[name] += line + "\n"
    return sections


def main():
    exe, doc = sys.argv[1], sys.argv[2]
    with open(doc, encoding="utf-8") as f:
        sections = sections_of(f.read())
    missing, counted = [], 0
    for cmd in SUBCOMMANDS:
        if cmd not in sections:
            missing.append(f"{cmd}: no '## plausible {cmd}' section")
            continue
        out = help_of(exe, cmd)
        if not all(part in out for part in EXIT_CODES):
            missing.append(f"{cmd}: --help does not state the exit codes (0, 1, 2, 130 or 143)")
        for flag in flags_of(out):
            counted += 1
            # `--flag` or `--flag VALUE`, `--flag=...` inside backticks.
            if not re.search(r"`" + re.escape(flag) + r"(?![A-Za-z0-9-])[^`]*`", sections[cmd]):
                missing.append(f"{cmd} {flag}")
    if missing:
        print(f"{doc} lacks flags that --help lists:", file=sys.stderr)
        for m in missing:
            print("  " + m, file=sys.stderr)
        return 1
    print(f"{counted} flags of {len(SUBCOMMANDS)} subcommands documented in {doc}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
