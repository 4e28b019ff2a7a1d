"""The conf file and airframes of a FINken swarm in Paparazzi's NPS (`make paparazzi-sim`).

- swarm_conf: a Paparazzi conf file with N aircraft <prefix>1..<prefix>N, ac_id 1..N, each as the first aircraft
  of a template conf (conf/userconf/finken/finken_conf.xml: radio, telemetry, flight plan, settings) but with the
  given airframe. The ids are the same in both runs of a comparison: every aircraft's random streams follow from
  the seed and its ac_id, so run 1 and run 2 draw the same streams.
- swarm_airframe: the example airframe with the run's seed (section FINKEN_WORLD, read by finken_world) and, for
  the comparison run, SWARM_USE_WALL_DETECTOR=FALSE on the swarm module (a -D of the whole target: swarm.c does
  not include generated/airframe.h); everything else as it is.
- bare_airframe: the example airframe without our world and the modules that need it (`make bench`'s Paparazzi
  NPS alone, against which the shared world's cost is measured).
"""
from lxml import etree

from finken.xml_errors import XmlInputError, parse_xml

COLOURS = ("red", "blue", "green", "orange", "magenta", "cyan", "yellow", "white", "brown", "pink")


def template_aircraft(conf_path):
    """The attributes of the first <aircraft> of a Paparazzi conf file."""
    root = parse_xml(conf_path)
    first = root.find("aircraft")
    if first is None:
        raise XmlInputError(conf_path, root.sourceline, "no <aircraft> to take as the template")
    return dict(first.attrib)


def swarm_conf(template, airframe, prefix, count):
    """The text of a conf file with `count` aircraft named prefix1.. (ac_id 1..count) flying `airframe` (a path
    relative to $PAPARAZZI_HOME/conf), otherwise as `template` (attributes of one <aircraft>)."""
    if count < 1:
        raise ValueError(f"a swarm needs at least one aircraft, not {count}")
    root = etree.Element("conf")
    root.append(etree.Comment(f" {count} aircraft for make paparazzi-sim (generated; ac_id 1..{count}) "))
    for ac_id in range(1, count + 1):
        attrs = dict(template, name=f"{prefix}{ac_id}", ac_id=str(ac_id), airframe=airframe,
                     gui_color=COLOURS[(ac_id - 1) % len(COLOURS)])
        etree.SubElement(root, "aircraft", attrs)
    etree.indent(root, space="  ")
    return etree.tostring(root, encoding="unicode") + "\n"


def _append(parent, child):
    """Append `child` to `parent` on a line of its own (one level deeper); returns it."""
    depth = len(list(parent.iterancestors()))
    (parent[-1] if len(parent) else parent).__setattr__("tail" if len(parent) else "text", "\n" + "  " * (depth + 1))
    parent.append(child)
    child.tail = "\n" + "  " * depth
    return child


def swarm_airframe(airframe_path, seed, use_wall_detector, arena=None):
    """The text of the airframe at `airframe_path` with the FINKEN_WORLD_SEED `seed`, when `use_wall_detector`
    is false SWARM_USE_WALL_DETECTOR=FALSE on its swarm module, and when `arena` is given (a path relative to
    $PAPARAZZI_HOME) that FINKEN_WORLD_ARENA. Raises XmlInputError naming the file when it has no swarm module or
    sets any of these defines already."""
    tree = etree.parse(str(airframe_path))
    root = tree.getroot()
    if root.xpath("//section[@prefix='FINKEN_WORLD_']/define[@name='SEED'] | //define[@name='FINKEN_WORLD_SEED']"):
        raise XmlInputError(airframe_path, None, "sets FINKEN_WORLD_SEED already: the run's seed cannot be set")
    sections = root.xpath("section[@prefix='FINKEN_WORLD_']")
    section = sections[0] if sections else _append(root, etree.Element("section", name="FINKEN_WORLD",
                                                                       prefix="FINKEN_WORLD_"))
    _append(section, etree.Element("define", name="SEED", value=str(int(seed))))
    if arena is not None:
        if root.xpath("//section[@prefix='FINKEN_WORLD_']/define[@name='ARENA'] | //define[@name='FINKEN_WORLD_ARENA']"):
            raise XmlInputError(airframe_path, None, "sets FINKEN_WORLD_ARENA already: the run's arena cannot be set")
        _append(section, etree.Element("define", name="ARENA", value=f'"{arena}"'))
    if not use_wall_detector:
        swarm = root.xpath("//firmware//module[@name='swarm']")
        if not swarm:
            raise XmlInputError(airframe_path, None, "no <module name=\"swarm\"> to turn the wall detector off in")
        if swarm[0].xpath(".//define[@name='SWARM_USE_WALL_DETECTOR']"):
            raise XmlInputError(airframe_path, swarm[0].sourceline, "the swarm module sets SWARM_USE_WALL_DETECTOR "
                                "already")
        _append(swarm[0], etree.Element("define", name="SWARM_USE_WALL_DETECTOR", value="FALSE"))
    return etree.tostring(tree, encoding="unicode") + "\n"


#: finken_world, and the modules whose NPS variants need it (the sensors) or need those (detector, swarm, recorder)
WORLD_MODULES = ("finken_world", "sonar_array", "virtual_ranging", "wall_detector", "swarm", "range_recorder")


def _remove(element):
    """Take `element` out of its parent, with the comment just before it; the indentation stays as it was."""
    comment = element.getprevious()
    if comment is not None and comment.tag is etree.Comment:
        _remove(comment)
    previous, parent = element.getprevious(), element.getparent()
    if element.getnext() is None:   # the last child: its tail indents the parent's closing tag
        if previous is not None:
            previous.tail = element.tail
        else:
            parent.text = element.tail
    parent.remove(element)


def bare_airframe(airframe_path):
    """The text of the airframe at `airframe_path` without the modules of WORLD_MODULES (wherever they are named)
    and the comment just before each: the same aircraft in Paparazzi's NPS alone, on its own flight model. Raises
    XmlInputError naming the file when it has no finken_world module."""
    tree = etree.parse(str(airframe_path))
    if not tree.xpath("//module[@name='finken_world']"):
        raise XmlInputError(airframe_path, None, "no <module name=\"finken_world\">: nothing to take out")
    for module in tree.xpath(" | ".join(f"//module[@name='{name}']" for name in WORLD_MODULES)):
        _remove(module)
    return etree.tostring(tree, encoding="unicode") + "\n"
