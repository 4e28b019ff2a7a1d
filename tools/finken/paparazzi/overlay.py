"""Lay our modules over a Paparazzi tree, and take them off again, without replacing any of Paparazzi's files.

What goes in (each file a new one; any that exists already stops the install before anything is written):
the module code (sw/airborne/modules, the NPS and Linux variants under sw/airborne/arch/*/modules), the simulator
core (sw/simulator/nps), the module descriptors (conf/modules, not our copy of module.dtd), the example FINken
aircraft (conf/airframes/finken, conf/flight_plans/finken, conf/userconf/finken) and the arena and sensor model
files (conf/arena, conf/sensor_models).

Two registries Paparazzi keeps in one file each are extended in place, between marker comments, and restored by
`remove`: the ABI messages of conf/abi_finken.xml go into the "airborne" class of conf/abi.xml; the telemetry
message of conf/telemetry/finken_messages.xml goes into conf/messages.xml, Paparazzi's file for custom pprzlink
messages (made from pprzlink's messages.xml when the tree has none; then `remove` deletes it). Run
`make static_h` in the tree afterwards so that Paparazzi regenerates its ABI and pprzlink headers.

A manifest (.finken_overlay at the tree's top) lists what was added; `remove` deletes those files unless they
were changed since (it names them and leaves them), the directories it created once empty, and the marked blocks.
"""
import hashlib
import re
from pathlib import Path

from lxml import etree

REPO_ROOT = Path(__file__).resolve().parents[3]
MANIFEST = ".finken_overlay"
OVERLAID_DIRS = ("sw/airborne/modules", "sw/airborne/arch/linux/modules", "sw/airborne/arch/sim/modules",
                 "sw/simulator/nps", "conf/modules", "conf/airframes/finken", "conf/flight_plans/finken",
                 "conf/userconf/finken", "conf/arena", "conf/sensor_models")
NOT_OVERLAID = {"conf/modules/module.dtd"}
ABI_SOURCE = "conf/abi_finken.xml"
TELEMETRY_SOURCE = "conf/telemetry/finken_messages.xml"
PPRZLINK_MESSAGES = "sw/ext/pprzlink/message_definitions/v1.0/messages.xml"
BEGIN, END = "<!-- finken overlay: begin -->", "<!-- finken overlay: end -->"


class OverlayError(RuntimeError):
    pass


def overlay_files(repo=REPO_ROOT):
    """Paths (relative, sorted) of our files that go into a tree."""
    files = []
    for d in OVERLAID_DIRS:
        files += [p.relative_to(repo).as_posix() for p in Path(repo, d).rglob("*") if p.is_file()]
    return sorted(f for f in files if f not in NOT_OVERLAID and "__pycache__" not in f)


def _sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _messages_of_class(xml_path, class_name):
    """The <message> elements (as text) of one msg_class of a pprzlink/ABI message file."""
    root = etree.parse(str(xml_path)).getroot()
    cls = root.find(f"msg_class[@name='{class_name}']")
    if cls is None:
        raise OverlayError(f"{xml_path}: no msg_class '{class_name}'")
    return [etree.tostring(m, encoding="unicode").strip() for m in cls.findall("message")]


def _ids_and_names(text, class_name):
    root = etree.fromstring(text.encode())
    cls = root.find(f"msg_class[@name='{class_name}']")
    return {(m.get("name"), int(m.get("id"))) for m in cls.findall("message")} if cls is not None else set()


def insert_messages(text, class_name, messages, where):
    """`text` (a message file) with `messages` added at the end of msg_class `class_name`, between the markers.
    Refuses a file already holding the markers, or a name or id the class has already."""
    if BEGIN in text:
        raise OverlayError(f"{where} already holds a finken overlay block: run 'overlay remove' first")
    taken = _ids_and_names(text, class_name)
    for m in messages:
        el = etree.fromstring(m.encode())
        name, mid = el.get("name"), int(el.get("id"))
        clash = [t for t in taken if t[0] == name or t[1] == mid]
        if clash:
            raise OverlayError(f"{where}: message {name} (id {mid}) collides with {clash[0][0]} (id {clash[0][1]}) "
                               f"in class {class_name}")
    opening = re.search(r'<msg_class\s+name="%s"[^>]*>' % re.escape(class_name), text)
    if opening is None:
        raise OverlayError(f"{where}: no msg_class '{class_name}'")
    closing = text.index("</msg_class>", opening.end())
    block = "\n    ".join([BEGIN] + messages + [END])
    return text[:closing] + "  " + block + "\n  " + text[closing:]


def strip_block(text):
    """`text` without the marked block (and the indentation insert_messages put before it)."""
    return re.sub(r"  " + re.escape(BEGIN) + r".*?" + re.escape(END) + r"\n  ", "", text, flags=re.S)


def _write_new(path, data):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "x", encoding="utf-8") as f:       # "x": never replaces a file
        f.write(data)


def install(tree, repo=REPO_ROOT):
    """Add our files and registry entries to `tree`; return the manifest lines. Nothing is written when any of
    our files exists in the tree already (all such paths are named)."""
    tree = Path(tree)
    if (tree / MANIFEST).exists():
        raise OverlayError(f"{tree / MANIFEST} exists: the overlay is installed already ('overlay remove' first)")
    for needed in ("conf/abi.xml", PPRZLINK_MESSAGES):
        if not (tree / needed).is_file():
            raise OverlayError(f"{tree} is not a Paparazzi tree with pprzlink: {needed} is missing")
    files = overlay_files(repo)
    existing = [f for f in files if (tree / f).exists()]
    if existing:
        raise OverlayError("these files exist in the tree already, nothing was written:\n  " + "\n  ".join(existing))
    abi_messages = _messages_of_class(repo / ABI_SOURCE, "airborne")
    telemetry = _messages_of_class(repo / TELEMETRY_SOURCE, "telemetry")
    abi_text = insert_messages((tree / "conf/abi.xml").read_text(), "airborne", abi_messages, tree / "conf/abi.xml")
    custom = tree / "conf/messages.xml"
    base = custom if custom.exists() else tree / PPRZLINK_MESSAGES
    messages_text = insert_messages(base.read_text(), "telemetry", telemetry, base)

    manifest = []
    created_dirs = sorted({p for f in files for p in Path(f).parents if str(p) != "." and not (tree / p).exists()},
                          key=lambda p: len(p.parts))
    manifest += [f"dir {d.as_posix()}" for d in created_dirs]
    for f in files:
        _write_new(tree / f, (repo / f).read_text(encoding="utf-8"))
        manifest.append(f"file {f} {_sha256(tree / f)}")
    (tree / "conf/abi.xml").write_text(abi_text)
    manifest.append("edit conf/abi.xml")
    if custom.exists():
        custom.write_text(messages_text)
        manifest.append("edit conf/messages.xml")
    else:
        _write_new(custom, messages_text)
        manifest.append(f"file conf/messages.xml {_sha256(custom)}")
    (tree / MANIFEST).write_text("\n".join(manifest) + "\n")
    return manifest


def remove(tree):
    """Take off what install added; return the files left because they were changed since."""
    tree = Path(tree)
    if not (tree / MANIFEST).is_file():
        raise OverlayError(f"{tree / MANIFEST} not found: the overlay is not installed in {tree}")
    changed, dirs = [], []
    for line in (tree / MANIFEST).read_text().splitlines():
        kind, rel, *rest = line.split(" ")
        path = tree / rel
        if kind == "dir":
            dirs.append(path)
        elif kind == "edit" and path.is_file():
            path.write_text(strip_block(path.read_text()))
        elif kind == "file" and path.is_file():
            if _sha256(path) == rest[0]:
                path.unlink()
            else:
                changed.append(rel)
    for d in sorted(dirs, key=lambda p: len(p.parts), reverse=True):
        for sub in sorted(d.rglob("*"), key=lambda p: len(p.parts), reverse=True):
            if sub.is_dir() and not any(sub.iterdir()):
                sub.rmdir()
        if d.is_dir() and not any(d.iterdir()):
            d.rmdir()
    (tree / MANIFEST).unlink()
    return changed
