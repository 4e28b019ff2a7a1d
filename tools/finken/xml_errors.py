"""XML reading with errors that name the file, the line and what was expected."""
from lxml import etree


class XmlInputError(ValueError):
    """A configuration file that cannot be used: `file:line: reason`."""

    def __init__(self, path, line, reason):
        self.path, self.line, self.reason = str(path), line, reason
        where = f"{self.path}:{line}" if line else self.path
        super().__init__(f"{where}: {reason}")


def parse_xml(path, dtd_path=None):
    """Parse `path` (and validate it against `dtd_path` if given); return the root element."""
    parser = etree.XMLParser(remove_comments=True)
    try:
        tree = etree.parse(str(path), parser)
    except OSError as err:
        raise XmlInputError(path, None, f"cannot read: {err}")
    except etree.XMLSyntaxError as err:
        raise XmlInputError(path, err.lineno, f"malformed XML: {err.msg}")
    if dtd_path is not None:
        with open(dtd_path, "rb") as f:
            dtd = etree.DTD(f)
        if not dtd.validate(tree):
            first = dtd.error_log.filter_from_errors()[0]
            raise XmlInputError(path, first.line, f"does not match {dtd_path}: {first.message}")
    return tree.getroot()


def require_attr(path, element, name):
    """The value of a required attribute, or an error naming the element and its line."""
    value = element.get(name)
    if value is None or value.strip() == "":
        raise XmlInputError(path, element.sourceline, f"<{element.tag}> needs a '{name}' attribute")
    return value.strip()
