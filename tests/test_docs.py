"""The documentation site builds in strict mode (a broken link, page or API reference fails), and
nothing in the repository points at files it does not contain."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
#: .md names that are files a command writes, not references to documents
WRITTEN = {"results.md"}
TEXT_SUFFIXES = {".py", ".md", ".yaml", ".yml", ".toml", ".txt", ".js", ".html", ".css", ".cfg", ""}


def repository_files() -> list[Path]:
    files = [ROOT / "README.md", ROOT / "Makefile", ROOT / "pyproject.toml", ROOT / "mkdocs.yml"]
    for folder in ("src", "tests", "docs", "benchmarks", ".ci"):
        files += [p for p in (ROOT / folder).rglob("*") if p.is_file() and p.suffix in TEXT_SUFFIXES
                  and "__pycache__" not in p.parts and "vendor" not in p.parts]  # vendor: npm's, git-ignored
    return files


def test_no_reference_to_files_outside_the_repository():
    markdown = {p.name for p in ROOT.rglob("*.md") if ".venv" not in p.parts and "site" not in p.parts} | WRITTEN
    missing = []
    for path in repository_files():
        text = path.read_text(errors="replace")
        for name in set(re.findall(r"(?<![\w/.-])([\w-]+\.md)\b", text)):
            if name not in markdown:
                missing.append(f"{path.relative_to(ROOT)}: {name}")
        if "papers/" in text and path.name != "test_docs.py":
            missing.append(f"{path.relative_to(ROOT)}: papers/")
    assert not missing, "references to files the repository does not contain:\n" + "\n".join(missing)


def test_site_builds_in_strict_mode(tmp_path):
    pytest.importorskip("mkdocs")
    pytest.importorskip("mkdocstrings_handlers.python")
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""),
               NO_MKDOCS_2_WARNING="1")
    # not -q: mkdocs counts only the warnings it logs, so a quiet strict build passes broken links
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(ROOT / "mkdocs.yml"),
                           "-d", str(tmp_path / "site")], cwd=ROOT, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    cli = (tmp_path / "site" / "cli" / "index.html").read_text()
    # the CLI reference is generated from the parsers: every command's options are there
    for text in ("robkin estimate", "--tip-link", "--optimize", "robkin check"):
        assert text in cli
    api = (tmp_path / "site" / "api" / "index.html").read_text()
    assert "manipulability" in api and "jacobian" in api
