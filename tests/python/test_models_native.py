"""The cffi declarations (sw/simulator/nps/nps_sensor_model.cdef) still match the C headers they mirror."""
import re

from finken import _native

HEADERS = ["nps_rng.h", "nps_gmm.h", "nps_condition.h", "nps_effect.h", "nps_sensor_model_ctx.h",
           "nps_sensor_model.h", "nps_sensor_model_xml.h"]


def _normalise(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    text = re.sub(r"\s+", " ", text)
    return re.sub(r"\s*([(),;*\[\]])\s*", r"\1", text)


def test_every_cdef_function_is_declared_the_same_in_a_header():
    headers = _normalise(" ".join((_native.CDEF_PATH.parent / h).read_text() for h in HEADERS))
    declarations = [d.strip() for d in _normalise(_native.CDEF_PATH.read_text()).split(";") if "(" in d]
    assert len(declarations) > 30
    missing = [d for d in declarations if d + ";" not in headers]
    assert missing == []
