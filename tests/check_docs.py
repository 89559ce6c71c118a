#!/usr/bin/env python3
"""The user documentation stays whole: README.md and docs/*.md link only to files of this repository.

Run by ctest (DocsLinks, tests/CMakeLists.txt) as `check_docs.py SOURCE_DIR`. Fails, naming the file
and line, when
  - a relative markdown link or image ([text](path), ![alt](path)) points at a file or directory
    that does not exist, or outside the repository, or at a #heading a markdown page does not have;
  - a backticked repository path (`docs/commands.md`, `src/...`, `include/...`, `tests/...`, `tools/...`,
    `cases/...`) outside code blocks names nothing that exists;
  - a source comment (src/, include/, tests/, tools/, cases/) cites a docs/*.md page that does not
    exist;
  - README.md has more than 300 lines, or mentions ../shared (files beside the clone, which a
    clone does not have), or README.md and docs/*.md cite issue numbers.
"""
import pathlib
import re
import sys

MAX_README_LINES = 300
ROOTS = ("docs", "src", "include", "tests", "tools", "cases")
# Paths that name what a run writes, or stand for many files: not checked.
GENERATED = {"out", "study", "trade", "build"}
PLACEHOLDER = re.compile(r"[*<>{}]|NNN|\.\.\.|\bN\*")
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
CODE = re.compile(r"`([^`\n]+)`")
REPO_PATH = re.compile(r"^(?:%s)/[A-Za-z0-9_./+-]*$" % "|".join(ROOTS))
ISSUE = re.compile(r"\bissues?\s+#?\d+|\(#\d+\)|\bPR\s+#?\d+", re.IGNORECASE)
DOC_CITE = re.compile(r"\bdocs/[A-Za-z0-9_-]+\.md\b")


def anchors(md: pathlib.Path) -> set:
    """The #anchors of a markdown page's headings, as GitHub makes them."""
    found, seen, fenced = set(), {}, False
    for line in md.read_text(encoding="utf-8").splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
        if fenced or not line.startswith("#"):
            continue
        slug = re.sub(r"[^a-z0-9 _-]", "", line.lstrip("#").strip().lower()).replace(" ", "-")
        k = seen.get(slug, 0)
        seen[slug] = k + 1
        found.add(slug if k == 0 else f"{slug}-{k}")
    return found


def inside(root: pathlib.Path, p: pathlib.Path) -> bool:
    try:
        p.resolve().relative_to(root.resolve())
        return True
    except ValueError:
        return False


def check_markdown(root: pathlib.Path, md: pathlib.Path, errors: list) -> None:
    rel = md.relative_to(root)
    fenced = False
    for n, line in enumerate(md.read_text(encoding="utf-8").splitlines(), 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            continue
        for m in LINK.finditer(line):
            target = m.group(1)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target):
                continue  # a URL
            if target.startswith("#"):
                if target[1:] not in anchors(md):
                    errors.append(f"{rel}:{n}: link {target!r}: no such heading in this page")
                continue
            path, _, anchor = target.partition("#")
            p = (md.parent / path)
            if not inside(root, p):
                errors.append(f"{rel}:{n}: link {target!r} points outside the repository")
            elif not p.exists():
                errors.append(f"{rel}:{n}: link {target!r}: no such file")
            elif anchor and p.suffix == ".md" and anchor not in anchors(p):
                errors.append(f"{rel}:{n}: link {target!r}: {path} has no heading #{anchor}")
        for m in CODE.finditer(line):
            token = m.group(1).strip()
            if not REPO_PATH.match(token) or PLACEHOLDER.search(token):
                continue
            parts = pathlib.PurePosixPath(token).parts
            if any(part in GENERATED for part in parts):
                continue
            if not (root / token).exists():
                errors.append(f"{rel}:{n}: `{token}`: no such file or directory in the repository")
        for m in ISSUE.finditer(line):
            errors.append(f"{rel}:{n}: cites an issue number ({m.group(0)!r}): say what it is instead")


def check_readme(root: pathlib.Path, errors: list) -> None:
    readme = root / "README.md"
    lines = readme.read_text(encoding="utf-8").splitlines()
    if len(lines) > MAX_README_LINES:
        errors.append(f"README.md: {len(lines)} lines, more than {MAX_README_LINES}: move detail to docs/")
    for n, line in enumerate(lines, 1):
        if "../shared" in line:
            errors.append(f"README.md:{n}: mentions ../shared, which is not in a clone")


def check_source_citations(root: pathlib.Path, errors: list) -> None:
    for top in ROOTS[1:]:
        for f in sorted((root / top).rglob("*")):
            if not f.is_file() or f.suffix not in {".cpp", ".hpp", ".h", ".py", ".sh", ".toml", ".txt", ""}:
                continue
            try:
                text = f.read_text(encoding="utf-8")
            except (UnicodeDecodeError, OSError):
                continue
            for n, line in enumerate(text.splitlines(), 1):
                for m in DOC_CITE.finditer(line):
                    if not (root / m.group(0)).exists():
                        errors.append(f"{f.relative_to(root)}:{n}: cites {m.group(0)}, which does not exist")


def main() -> int:
    if len(sys.argv) != 2:
        print("usage: check_docs.py SOURCE_DIR", file=sys.stderr)
        return 2
    root = pathlib.Path(sys.argv[1])
    pages = [root / "README.md"] + sorted((root / "docs").glob("*.md"))
    errors: list = []
    for md in pages:
        check_markdown(root, md, errors)
    check_readme(root, errors)
    check_source_citations(root, errors)
    for e in errors:
        print(e)
    print(f"checked {len(pages)} pages: {len(errors)} problem(s)")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
