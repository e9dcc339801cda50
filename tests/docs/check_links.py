#!/usr/bin/python3
"""Every relative link of the user documentation resolves (ctest Docs.LinksResolve).

Usage: check_links.py SOURCE_DIR

Checks README.md, ARCHITECTURE.md and docs/*.md: each [text](target) and ![alt](target) outside code (fenced
blocks and `inline code`) whose target is not a URL must name an existing file or folder, relative to the page;
a #anchor (alone or after a .md target) must be a heading of that page, spelled as GitHub spells it (lower case,
punctuation dropped, spaces as hyphens, a repeated heading gets -1, -2, ...). Also: the README stays a user guide
of at most 300 lines. Prints every broken link as FILE:LINE: target (reason) and exits 1 if there is one.
"""
import os
import re
import sys
import unicodedata

README_MAX_LINES = 300
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^\s*(```|~~~)")


def strip_fences(lines):
    """The lines with fenced code blocks blanked (line numbers kept)."""
    out, fenced = [], False
    for line in lines:
        if FENCE.match(line):
            fenced = not fenced
            out.append("")
            continue
        out.append("" if fenced else line)
    return out


def strip_code(lines):
    """As strip_fences, and inline code spans removed: a link written as code is not a link."""
    return [re.sub(r"`[^`]*`", "", line) for line in strip_fences(lines)]


def slug(heading):
    """GitHub's anchor of a heading: markdown emphasis and code marks dropped, lower case, letters, digits,
    spaces, hyphens and underscores kept, spaces turned into hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link in a heading: its text
    text = text.replace("`", "").replace("*", "")
    text = text.strip().lower()
    kept = []
    for ch in text:
        cat = unicodedata.category(ch)
        if ch in " -_" or cat[0] in "LN":
            kept.append(ch)
    return "".join(kept).replace(" ", "-")


def anchors(path, cache={}):
    path = os.path.abspath(path)
    if path not in cache:
        with open(path, encoding="utf-8") as f:
            lines = strip_fences(f.read().splitlines())
        seen, found = {}, set()
        for line in lines:
            m = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
            if not m:
                continue
            s = slug(m.group(2))
            n = seen.get(s, 0)
            found.add(s if n == 0 else "%s-%d" % (s, n))
            seen[s] = n + 1
        cache[path] = found
    return cache[path]


def check(page, errors):
    with open(page, encoding="utf-8") as f:
        raw = f.read().splitlines()
    for no, line in enumerate(strip_code(raw), 1):
        for m in LINK.finditer(line):
            target = m.group(1)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
                continue
            path, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
            where = "%s:%d: %s" % (os.path.relpath(page), no, target)
            if not os.path.exists(dest):
                errors.append(where + " (no such file)")
                continue
            if anchor:
                if not dest.endswith(".md") or not os.path.isfile(dest):
                    errors.append(where + " (an anchor into a file that is not markdown)")
                elif anchor not in anchors(dest):
                    errors.append(where + " (no heading with this anchor in %s)" % os.path.relpath(dest))


def self_test():
    """The checker itself on a tiny tree: the good links pass, each planted fault is reported."""
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        os.makedirs(os.path.join(d, "docs"))
        with open(os.path.join(d, "docs", "a.md"), "w", encoding="utf-8") as f:
            f.write("# Page A\n## Camera observables (diagnosis.md §2)\n## Twice\n## Twice\n"
                    "```sh\n# not a heading\n[skipped](missing-in-code.md)\n```\n"
                    "[ok](../README.md) [ok](#camera-observables-diagnosismd-2) [ok](#twice-1) `[code](nope.md)`\n"
                    "[bad](missing.md) [bad](#not-a-heading) [bad](../README.md#nowhere)\n")
        with open(os.path.join(d, "README.md"), "w", encoding="utf-8") as f:
            f.write("# R\n## Set up: `a` and *b*\n[ok](docs/a.md#page-a) [ok](#set-up-a-and-b) ![ok](docs)\n"
                    "[ok](https://example.org/x.md)\n")
        with open(os.path.join(d, "ARCHITECTURE.md"), "w", encoding="utf-8") as f:
            f.write("# A\n")
        errors = []
        for page in ["README.md", "docs/a.md"]:
            cwd = os.getcwd()
            os.chdir(d)
            try:
                check(page, errors)
            finally:
                os.chdir(cwd)
    got = sorted(e.split(": ", 1)[1].split(" (")[0] for e in errors)
    want = sorted(["missing.md", "#not-a-heading", "../README.md#nowhere"])
    if got != want:
        print("self-test FAILED: reported %s, expected %s" % (got, want))
        return False
    return True


def main():
    if not self_test():
        return 1
    src = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    os.chdir(src)
    pages = ["README.md", "ARCHITECTURE.md"]
    pages += sorted(os.path.join("docs", p) for p in os.listdir("docs") if p.endswith(".md"))
    errors = []
    for page in pages:
        check(page, errors)
    with open("README.md", encoding="utf-8") as f:
        n = len(f.read().splitlines())
    if n > README_MAX_LINES:
        errors.append("README.md: %d lines, more than %d (move detail to docs/)" % (n, README_MAX_LINES))
    for e in errors:
        print(e)
    print("%d pages checked, %d problems" % (len(pages), len(errors)))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
