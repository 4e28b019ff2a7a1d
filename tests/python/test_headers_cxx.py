"""Every header of the modules compiles on its own as C and as C++, and declares its functions with C linkage.

Paparazzi's C++ flight models (NPS's JSBSim glue, for one) include generated/modules.h, which includes every module's
header: a header must parse as C++, and the functions it declares must keep C linkage there (the guard
`#ifdef __cplusplus extern "C" { #endif`, after the includes), or the C++ side links against mangled names that the C
objects do not define.

Checked for each header under sw/airborne/modules and sw/airborne/arch/*/modules (found, not listed), with the include
paths of the Makefile's C build (AIRBORNE_INC, and the arch the header belongs to; sim for the arch-independent ones):
  - C:   gcc -fsyntax-only -std=gnu99 -Wall -Wextra -Werror
  - C++: g++ -fsyntax-only -x c++
  - C linkage: the functions the header declares with external linkage (as gcc lists them, -aux-info), referenced
    from a C++ source and compiled, must appear in the object under their plain C names, not mangled ones.
  - the guard: opened after the header's last #include (a C++ standard header such as <cmath> must not be included
    inside extern "C") and closed.
"""
import re
import subprocess
from pathlib import Path

import pytest

from airborne_build import REPO, airborne_flags, compile_or_fail, require_abi_header

HEADERS = sorted(p.relative_to(REPO).as_posix() for pattern in ("sw/airborne/modules/**/*.h",
                                                                  "sw/airborne/arch/*/modules/**/*.h")
                 for p in REPO.glob(pattern))

GUARD_OPEN = '#ifdef __cplusplus\nextern "C" {\n#endif\n'
GUARD_CLOSE = '#ifdef __cplusplus\n}\n#endif\n'

# gcc -aux-info: one line per function declared, e.g.
#   /* sw/airborne/modules/sonar/sonar_array.h:110:NC */ extern void sonar_array_init (void);
AUX_EXTERN = re.compile(r"^/\* (?P<file>.+?):\d+:N[CF] \*/ extern [^(]*?(?P<name>\w+) \(")


def include_flags(header, build_dir):
    """The Makefile's flags for a source of the header's arch (sw/airborne/arch/<arch>/...; sim otherwise)."""
    arch = re.match(r"sw/airborne/arch/(\w+)/", header)
    return airborne_flags(build_dir, arch.group(1) if arch else "sim")


def extern_functions(header, flags, tmp_path, cwd=REPO):
    """Compile the header as C (the check above) and return the functions it declares with external linkage."""
    aux = tmp_path / "aux-info.txt"
    compile_or_fail("C", ["gcc", "-fsyntax-only", "-std=gnu99", "-Wall", "-Wextra", "-Werror", "-aux-info", aux,
                          *flags, "-x", "c", header], cwd)
    names = []
    for line in aux.read_text().splitlines():
        m = AUX_EXTERN.match(line)
        if m and Path(m["file"]) == Path(header):
            names.append(m["name"])
    return names


def mangled_functions(header, names, flags, tmp_path, cwd=REPO):
    """The names among `names` that a C++ source including the header does not reference under their C names."""
    source = tmp_path / "refs.cpp"
    refs = ",\n".join(f"  reinterpret_cast<const void *>(&{name})" for name in names)
    source.write_text(f'#include "{(cwd / header).resolve()}"\nconst void *finken_refs[] = {{\n{refs}\n}};\n')
    obj = tmp_path / "refs.o"
    compile_or_fail("C++ linkage check", ["g++", "-c", *flags, source, "-o", obj], cwd)
    nm = subprocess.run(["nm", "--undefined-only", "--format=just-symbols", obj], capture_output=True, text=True,
                        check=True)
    undefined = set(nm.stdout.split())
    return [name for name in names if name not in undefined]


def guard_problems(text):
    """What is wrong with the header's extern "C" guard (an empty list: nothing)."""
    opened = text.find(GUARD_OPEN)
    if opened < 0 or GUARD_CLOSE not in text[opened:]:
        return ['no extern "C" guard (#ifdef __cplusplus / extern "C" { / #endif ... and its closing })']
    return [f"#include inside the guard: {line}" for line in text[opened:].splitlines()
            if line.lstrip().startswith("#include")]


def check_header(header, build_dir, tmp_path, cwd=REPO):
    """Every check of the module docstring, failing with the compiler's or the checker's message."""
    flags = include_flags(header, build_dir)
    names = extern_functions(header, flags, tmp_path, cwd)
    compile_or_fail("C++", ["g++", "-fsyntax-only", "-x", "c++", *flags, header], cwd)
    if names:
        mangled = mangled_functions(header, names, flags, tmp_path, cwd)
        assert not mangled, f"{header}: C++ linkage (mangled names) for {', '.join(mangled)}: extern \"C\" missing"
    problems = guard_problems((cwd / header).read_text())
    assert not problems, f"{header}: " + "; ".join(problems)


@pytest.fixture
def abi_header(build_dir):
    require_abi_header(build_dir)


def test_the_headers_are_found():
    assert "sw/airborne/modules/sonar/sonar_array.h" in HEADERS
    assert any(h.startswith("sw/airborne/arch/linux/modules/") for h in HEADERS)


@pytest.mark.parametrize("header", HEADERS)
def test_header_compiles_as_c_and_cxx_with_c_linkage(header, build_dir, tmp_path, abi_header):
    check_header(header, build_dir, tmp_path)


def test_a_header_without_the_guard_is_caught(build_dir, tmp_path, abi_header):
    """The checks themselves: a function declared outside extern "C" fails on its mangled name, an include inside
    the guard on the include; the same header correctly guarded passes."""
    def write(body):
        (tmp_path / "t.h").write_text(f"#ifndef T_H\n#define T_H\n{body}#endif\n")

    include, declaration = "#include <stdint.h>\n", "extern int t_twice(int32_t x);\n"
    write(include + declaration)
    with pytest.raises(AssertionError, match="mangled names.*t_twice"):
        check_header("t.h", build_dir, tmp_path, cwd=tmp_path)
    write(GUARD_OPEN + include + declaration + GUARD_CLOSE)
    with pytest.raises(AssertionError, match="#include inside the guard"):
        check_header("t.h", build_dir, tmp_path, cwd=tmp_path)
    write(include + GUARD_OPEN + declaration + GUARD_CLOSE)
    check_header("t.h", build_dir, tmp_path, cwd=tmp_path)
