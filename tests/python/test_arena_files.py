"""The arena files made from another one: conf/arena/swarmlab_16.xml is SwarmLab scaled for 16 copters at the
crowding of 8 in SwarmLab (make sim's "wall detector in a crowd"), and must stay what finken.bench.arena made."""
import math

import pytest
from lxml import etree

from finken.bench.arena import arena_size_m, scaled_arena

#: attributes that scaled_arena multiplies by the factor (the others keep their text)
SCALED = {("point", "x"), ("point", "y"), ("wall", "wallWidth")}


def _elements(root):
    """(tag, attributes) of every element, in document order (comments left out)."""
    return [(el.tag, dict(el.attrib)) for el in root.iter() if isinstance(el.tag, str)]


def test_swarmlab_16_is_swarmlab_scaled_to_the_density_of_8_copters(repo):
    path = repo / "conf" / "arena" / "swarmlab_16.xml"
    made = _elements(scaled_arena(repo / "conf" / "arena" / "swarmlab.xml", 8, 20).getroot())
    written = _elements(etree.parse(str(path)).getroot())
    assert [tag for tag, _ in written] == [tag for tag, _ in made]
    for (tag, attributes), (_, expected) in zip(written, made):
        assert set(attributes) == set(expected), tag
        for name, value in attributes.items():
            if tag == "arena" and name == "name":
                assert value == "swarmlab_16"
            elif (tag, name) in SCALED:
                assert float(value) == pytest.approx(float(expected[name]), abs=1e-9), (tag, name)
            else:
                assert value == expected[name], (tag, name)
    width, depth = arena_size_m(path)
    assert (width, depth) == pytest.approx((3.0 * math.sqrt(2.0), 4.0 * math.sqrt(2.0)), abs=1e-9)
    assert width * depth / 16 == pytest.approx(3.0 * 4.0 / 8, abs=1e-9)      # 1.5 m^2 per copter, as 8 in SwarmLab


def test_the_c_loader_accepts_swarmlab_16(repo, arena_native):
    ffi, lib = arena_native
    err = ffi.new("char[]", 512)
    arena = lib.nps_arena_load(str(repo / "conf" / "arena" / "swarmlab_16.xml").encode(), err, 512)
    assert arena != ffi.NULL, ffi.string(err).decode()
    lib.nps_arena_free(arena)
