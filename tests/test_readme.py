"""The README is a user's guide: short, no model-version history, and its xarray snippet
runs on the output of the quick run it tells a user to make first (``make smoke``)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
README = (REPO / "README.md").read_text(encoding="utf-8")


def _python_blocks(text: str) -> list:
    return re.findall(r"```python\n(.*?)```", text, flags=re.DOTALL)


def test_readme_is_short_and_has_no_model_version_history():
    assert len(README.encode("utf-8")) < 12 * 1024
    assert "What changed with MODEL_VERSION" not in README
    assert "Before that (MODEL_VERSION" not in README


def test_readme_starts_with_the_quick_run():
    commands = re.findall(r"^make (\w+)", README, flags=re.MULTILINE)
    assert commands[0] == "smoke"


def test_the_readme_snippet_runs_on_the_smoke_output(smoke_run, tmp_path, monkeypatch):
    blocks = _python_blocks(README)
    assert len(blocks) == 1, "the README has one xarray snippet"
    assert '"results/smoke/' in blocks[0]
    # the snippet's relative paths, as after `make smoke` in the repository
    (tmp_path / "results").symlink_to(smoke_run.out.parent, target_is_directory=True)
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(blocks[0], "README.md", "exec"), namespace)
    # what it selected is what the files hold
    assert namespace["delta_r"].dims == ("elapsed_time",)
    assert namespace["startup"].shape == (3, 3)
    assert namespace["slope"].dims == ("displacement_metric",)
    for name in ("ds", "m", "f"):
        namespace[name].close()


@pytest.mark.parametrize("path", ["docs/model.md", "docs/performance.md", "docs/validation.md", "docs/inputs.md",
                                  "docs/outputs.md", "CHANGELOG.md"])
def test_the_readme_links_resolve(path):
    assert f"({path})" in README and (REPO / path).is_file()
