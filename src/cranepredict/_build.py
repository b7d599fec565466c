"""cffi build script (API mode): compiles csrc/ into ``cranepredict._cranepredict``.

The cdef is read from the public header between CRANE_CDEF_BEGIN and CRANE_CDEF_END, so the
declarations are written once; crane_model's and crane_work's bodies are replaced by "...;" (opaque:
size only).
The Python extension always uses the double build.
"""

from __future__ import annotations

import glob
import os
import re

from cffi import FFI

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CSRC = os.path.join(ROOT, "csrc")


def header_cdef(path: str = os.path.join(CSRC, "crane.h")) -> str:
    with open(path, encoding="utf-8") as f:
        text = f.read()
    m = re.search(r"/\* CRANE_CDEF_BEGIN \*/(.*)/\* CRANE_CDEF_END \*/", text, re.S)
    if m is None:
        raise RuntimeError(f"{path}: CRANE_CDEF_BEGIN/END markers not found")
    # crane_model is opaque to the binding: cffi takes its size from the real header at compile
    # time, and Python never reads its fields (crane.h: they are the core's, not an interface).
    cdef, n = re.subn(r"typedef struct \{[^{}]*\} crane_model;", "typedef struct { ...; } crane_model;",
                      m.group(1))
    if n != 1:
        raise RuntimeError(f"{path}: the crane_model typedef was not found in the CDEF section")
    # crane_work (the predictions' working storage) likewise; its parts between the markers are
    # the core's types, which the binding does not declare.
    cdef, n = re.subn(r"/\* CRANE_WORK_BEGIN \*/.*/\* CRANE_WORK_END \*/",
                      "typedef struct { ...; } crane_work;", cdef, flags=re.S)
    if n != 1:
        raise RuntimeError(f"{path}: the CRANE_WORK_BEGIN/END markers were not found in the CDEF section")
    return "typedef double crane_real;\n" + cdef


def core_sources() -> list:
    return sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(CSRC, "*.c")))


ffibuilder = FFI()
ffibuilder.cdef(header_cdef())
ffibuilder.set_source(
    "cranepredict._cranepredict",
    '#include "crane.h"',
    sources=core_sources(),
    include_dirs=[os.path.relpath(CSRC, ROOT)],
    extra_compile_args=["-std=c99", "-O3"],
    libraries=["m"],
)

if __name__ == "__main__":
    ffibuilder.compile(verbose=True)
