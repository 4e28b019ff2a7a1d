"""Read a sweep file (YAML, PyYAML's safe subset) keeping the line of every key, so that an error can name the
file, the line and the key."""
import yaml


class SweepFileError(ValueError):
    """A sweep file refused: `file:line: key: reason` (line and key when known)."""

    def __init__(self, path, line, key, reason):
        where = f"{path}:{line}" if line else str(path)
        super().__init__(f"{where}: {key}: {reason}" if key else f"{where}: {reason}")
        self.path, self.line, self.key, self.reason = str(path), line, key, reason


class Mapping(dict):
    """A YAML mapping whose `lines[key]` is the line (from 1) where the key is written."""

    def __init__(self):
        super().__init__()
        self.lines = {}


class _Loader(yaml.SafeLoader):
    """SafeLoader whose mappings are Mapping objects; a key given twice is refused (PyYAML keeps the last)."""


def _mapping(loader, node):
    loader.flatten_mapping(node)
    result = Mapping()
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=True)
        line = key_node.start_mark.line + 1
        if not isinstance(key, str):
            raise SweepFileError(key_node.start_mark.name, line, key, "a key must be a name")
        if key in result:
            raise SweepFileError(key_node.start_mark.name, line, key,
                                 f"given twice (first at line {result.lines[key]})")
        result[key] = loader.construct_object(value_node, deep=True)
        result.lines[key] = line
    return result


_Loader.add_constructor("tag:yaml.org,2002:map", _mapping)


def load_yaml(path):
    """The document of the YAML file at `path`, which must be a mapping. Raises SweepFileError (OSError when the
    file cannot be read)."""
    with open(path, "rb") as f:   # PyYAML decodes, and names a byte that is not UTF-8
        try:
            document = yaml.load(f, Loader=_Loader)
        except yaml.MarkedYAMLError as err:
            mark = err.problem_mark or err.context_mark
            raise SweepFileError(path, mark.line + 1 if mark else None, None, f"not YAML: {err.problem}") from None
        except yaml.YAMLError as err:
            raise SweepFileError(path, None, None, f"not YAML: {err}") from None
    if not isinstance(document, Mapping):
        raise SweepFileError(path, 1, None, "expected a mapping of keys (airframe:, seeds:, ...)")
    return document
