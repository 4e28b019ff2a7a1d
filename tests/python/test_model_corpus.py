"""The shared corpus of sensor models (tests/data/models, errors listed in expected.txt) through the Python tools:
every file of good/ loads, every file of bad/ is refused with the error the list gives, the same files and the
same messages as the C loaders (tests/c/nps/test_sensor_model_corpus.c). A .xml file is read with
SensorModel.load, a .txt file holds the one-line form (SensorModel.from_string of its text, named by its path).
"""
from pathlib import Path

import pytest

from finken import models as M

REPO = Path(__file__).resolve().parents[2]
CORPUS = Path("tests/data/models")   # relative to the repository root, as the C test names the files


def expected_errors():
    """{file in bad/: (line, reason)} from expected.txt ("file line reason", '#' comments)."""
    entries = {}
    for row in (REPO / CORPUS / "expected.txt").read_text().splitlines():
        if row.strip() and not row.startswith("#"):
            name, line, reason = row.split(" ", 2)
            assert name not in entries, f"{name} is listed twice"
            entries[name] = (int(line), reason)
    return entries


EXPECTED = expected_errors()


def load(path):
    if path.suffix == ".txt":
        return M.SensorModel.from_string(path.read_bytes().decode(), origin=str(path))
    return M.SensorModel.load(path)


@pytest.fixture(autouse=True)
def at_the_repository_root(monkeypatch):
    monkeypatch.chdir(REPO)


def test_every_bad_file_is_listed_once():
    assert sorted(p.name for p in (REPO / CORPUS / "bad").iterdir()) == sorted(EXPECTED)


@pytest.mark.parametrize("name", sorted(p.name for p in (REPO / CORPUS / "good").iterdir()))
def test_a_good_model_loads_and_writes_back(name):
    model = load(CORPUS / "good" / name)
    assert M.SensorModel.from_xml(model.to_xml()) == model


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_a_bad_model_is_refused_with_its_error(name):
    line, reason = EXPECTED[name]
    path = CORPUS / "bad" / name
    with pytest.raises(M.ModelError) as info:
        load(path)
    message = str(info.value)
    where = f"{path}:{line}: "
    assert message.startswith(where) and reason in message[len(where):], message
    assert (info.value.path, info.value.line) == (str(path), line)
