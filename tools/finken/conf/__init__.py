"""Paparazzi's configuration files, read as Paparazzi reads them (our host's generator and the sweeps use them).

    airframe            an airframe file: the modules of one firmware target, their defines, the sections
    module_descriptor   module descriptors (conf/modules/*.xml, module.dtd) for one build target
    module_deps         a descriptor's <dep> (Paparazzi's sw/lib/ocaml/module.ml and aircraft.ml)
    airframe_modules    an airframe's modules for one target: descriptors, dependencies, defines
"""
