"""Every Markdown table the program writes renders: each row has as many cells as its header.

A `|` inside a cell (the `max |dbeta|` column of compare.md, a file name) must be escaped (`\\|`), or the row
splits into more cells than the header and the table does not render. The tables of predict, compare, fit-pid,
diagnose (one object, and per object with its overview), forecast-study, validate-diagnosis and reproduce (report.md)
are rendered here from runs on real pushes (among them one whose force sensor is frozen, a listed skip) and on a few
simulated trials, and predict's with an own object (--shapes)."""
import json
import re
import subprocess
from pathlib import Path

import pytest

from conftest import run_cli

UNESCAPED_BAR = re.compile(r"(?<!\\)\|")


def tables(text):
    """The Markdown tables of `text`: lists of consecutive lines that start with '|'."""
    found, current = [], []
    for line in text.splitlines():
        if line.startswith("|"):
            current.append(line)
        elif current:
            found.append(current)
            current = []
    if current:
        found.append(current)
    return found


def cell_count(row):
    # Cells lie between unescaped bars: "| a | b \\| c |" has 2.
    return len(UNESCAPED_BAR.findall(row.strip())) - 1


def bad_rows(folder):
    """(file, header, row) for every row whose cell count is not its header's; and how many tables were read."""
    bad, count = [], 0
    for md in sorted(Path(folder).rglob("*.md")):
        for table in tables(md.read_text()):
            count += 1
            header = table[0]
            assert len(table) >= 2 and re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", table[1].strip()), \
                f"{md.name}: a table without a separator row under its header: {header}"
            for row in table[1:]:
                if cell_count(row) != cell_count(header):
                    bad.append((md.name, header, row))
    return bad, count


def test_the_checker_sees_an_unescaped_bar():
    # The check itself: compare.md's header as it was written before (18 cells against the 14 of its rows).
    header = "| estimator | max |dbeta| | x |"
    assert cell_count(header) == 5
    assert cell_count("| estimator | max \\|dbeta\\| | x |") == 3


@pytest.fixture(scope="module")
def pushes(data_dir):
    abs_dir = data_dir / "abs"
    hexagon = sorted(abs_dir.glob("*shape=hex_a=0_v=50*.h5"))[0]
    ellipse = sorted(abs_dir.glob("*shape=ellip1_a=0_v=20*.h5"))[0]
    frozen = sorted(abs_dir.glob("*shape=rect1_*.h5"))[0]
    return [str(hexagon), str(ellipse), str(frozen)]


@pytest.mark.parametrize("command", [
    ["predict", "{files}", "--out", "{out}", "--jobs", "1"],
    ["compare", "{files}", "--out", "{out}", "--jobs", "1"],
    ["fit-pid", "{files}", "--out", "{out}", "--per-push", "--max-iterations", "3", "--jobs", "1"],
])
def test_every_table_of_a_batch_command_renders(executable, pushes, tmp_path, command):
    out = tmp_path / command[0]
    args = []
    for a in command:
        args += pushes if a == "{files}" else [str(out) if a == "{out}" else a]
    run_cli(executable, *args)  # exit 0: the frozen-sensor push is a listed skip
    bad, count = bad_rows(out)
    assert count > 0, f"{command[0]} wrote no Markdown table"
    assert not bad, "rows whose cell count is not their header's:\n" + "\n".join(f"{f}: {h}\n  {r}" for f, h, r in bad)


def test_every_table_of_the_reproduction_renders(executable, data_dir, tmp_path):
    out = tmp_path / "reproduction"
    run_cli(executable, "reproduce", "--data", data_dir, "--out", out)
    bad, count = bad_rows(out)
    assert count >= 8, f"report.md holds {count} tables"
    assert not bad, "rows whose cell count is not their header's:\n" + "\n".join(f"{f}: {h}\n  {r}" for f, h, r in bad)
    report = (out / "report.md").read_text()
    # No table cell or figure caption prints a negative zero.
    assert not re.search(r"(?<![0-9.])-0\.0+(?![0-9]*[1-9])\b", report), "report.md prints -0.0"


@pytest.mark.parametrize("command", [
    ["diagnose", "{files}", "--out", "{out}", "--jobs", "1"],
    ["diagnose", "{files}", "--out", "{out}", "--per-object", "--jobs", "1"],
    ["forecast-study", "{files}", "--out", "{out}", "--jobs", "1"],
])
def test_every_table_of_the_diagnosis_and_forecast_renders(executable, data_dir, tmp_path, command):
    abs_dir = data_dir / "abs"
    files = [str(f) for f in sorted(abs_dir.glob("*shape=hex_a=0_v=50*.h5"))[:4]]
    if "--per-object" in command:
        files += [str(f) for f in sorted(abs_dir.glob("*shape=ellip1_a=0_v=20*.h5"))[:4]]
    out = tmp_path / command[0]
    args = []
    for a in command:
        args += files if a == "{files}" else [str(out) if a == "{out}" else a]
    proc = subprocess.run([executable, *args], capture_output=True, text=True)
    assert proc.returncode in (0, 1), proc.stderr
    bad, count = bad_rows(out)
    assert count > 0, f"{command[0]} wrote no Markdown table"
    assert not bad, "rows whose cell count is not their header's:\n" + "\n".join(f"{f}: {h}\n  {r}" for f, h, r in bad)


def test_every_table_of_the_validation_renders(executable, tmp_path):
    out = tmp_path / "validation"
    run_cli(executable, "validate-diagnosis", "--trials", "1", "--kinds", "none,viscous_friction", "--out", out,
            "--jobs", "1")
    bad, count = bad_rows(out)
    assert count >= 4, f"validation.md holds {count} tables"
    assert not bad, "rows whose cell count is not their header's:\n" + "\n".join(f"{f}: {h}\n  {r}" for f, h, r in bad)


def test_the_tables_of_an_own_object_render(executable, pushes, tmp_path):
    shapes = tmp_path / "own.json"
    shapes.write_text(json.dumps({"shapes": [{"name": "puck", "mass_kg": 0.9, "inertia_kgm2": 0.0012,
                                              "outline": {"kind": "circle", "radius_m": 0.0525}}]}))
    out = tmp_path / "predict"
    run_cli(executable, "predict", pushes[1], "--shapes", shapes, "--shape", "puck", "--out", out, "--jobs", "1")
    bad, count = bad_rows(out)
    assert count > 0 and not bad, bad
    assert (out / "tables.md").exists()
