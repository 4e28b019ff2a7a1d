"""A module descriptor's <dep> as Paparazzi reads it (sw/lib/ocaml/module.ml and aircraft.ml).

- <depends> and <recommends>: entries separated by commas (spaces around a comma ignored, nothing else splits);
  each entry is alternatives separated by '|', or '!a|b'. An alternative is a module name, or a functionality when
  it starts with '@'. An entry holds when some loaded module or provided functionality matches it; for '!a|b' that
  is any one that is neither a nor b (Paparazzi's `List.exists (eval_bool p) ...` over what is present).
- <provides>: functionalities separated by commas, written without '@' ('sonar' provides '@sonar').
- A required module name is loaded as a dependency; a missing descriptor is an error. A required functionality
  must be provided by a loaded module (or by a module loaded by name).
"""
import re
from dataclasses import dataclass

_COMMA = re.compile(r"[ \t]*,[ \t]*")


def comma_list(text):
    """Paparazzi's parse_comma_list: Str.split on commas; empty pieces (at the ends) are dropped."""
    return [item for item in _COMMA.split(text or "") if item]


@dataclass(frozen=True)
class Requirement:
    """One <depends> entry and when it holds (see the module docstring)."""
    text: str
    alternatives: tuple[str, ...]
    negated: bool

    @classmethod
    def parse(cls, text):
        negated = text.startswith("!")
        body = text[1:] if negated else text
        return cls(text, tuple(alt for alt in body.split("|") if alt), negated)

    def satisfied_by(self, present):
        if self.negated:
            return any(name not in self.alternatives for name in present)
        return any(alt in present for alt in self.alternatives)

    def module_to_load(self):
        """A single plain module name is loaded by Paparazzi; any other form is only checked."""
        if not self.negated and len(self.alternatives) == 1 and not self.alternatives[0].startswith("@"):
            return self.alternatives[0]
        return None


def parse_depends(text):
    return [Requirement.parse(entry) for entry in comma_list(text)]


def parse_provides(text):
    return ["@" + name for name in comma_list(text)]
