"""One version everywhere: CMakeLists.txt's project(VERSION), `pushpred --version`, the Python module, the CMake
package's version file, CITATION.cff and the changelog's latest release."""
import os
import re
from pathlib import Path

import pushpred
from conftest import run_cli

SOURCE = Path(os.environ.get("PUSHPRED_SOURCE_DIR", Path(__file__).resolve().parents[2]))


def project_version():
    text = (SOURCE / "CMakeLists.txt").read_text()
    return re.search(r"project\(pushpred VERSION (\d+\.\d+\.\d+)", text).group(1)


def test_versions_agree(executable):
    version = project_version()
    assert pushpred.__version__ == version
    assert run_cli(executable, "--version").stdout.strip() == f"pushpred {version}"
    binary = os.environ.get("PUSHPRED_BINARY_DIR")
    if binary:
        config = (Path(binary) / "pushpredConfigVersion.cmake").read_text()
        assert f'set(PACKAGE_VERSION "{version}")' in config
    citation = (SOURCE / "CITATION.cff").read_text()
    assert re.search(r"^version: (\S+)$", citation, re.M).group(1) == version
    changelog = (SOURCE / "CHANGELOG.md").read_text()
    releases = re.findall(r"^## \[(\d+\.\d+\.\d+)\]", changelog, re.M)
    assert releases and releases[0] == version
