# Metadata lives in pyproject.toml; setup.py exists only because setuptools takes cffi_modules here.
# The extension is built for the stable ABI (cffi compiles it with Py_LIMITED_API; its file is
# _cranepredict.abi3.so), so one wheel per platform serves every CPython from 3.10 on.
import glob
import os
import shutil

from setuptools import setup
from setuptools.command.build_py import build_py


class build_py_with_core(build_py):
    """Also ships the C core's sources (csrc/*.c, *.h) as cranepredict/fmu/core/: an FMU exported
    from an installed wheel is compiled from them (cranepredict.fmu; docs/fmu.md)."""

    def run(self):
        super().run()
        here = os.path.dirname(os.path.abspath(__file__))
        dst = os.path.join(self.build_lib, "cranepredict", "fmu", "core")
        os.makedirs(dst, exist_ok=True)
        for f in glob.glob(os.path.join(here, "csrc", "*.[ch]")):
            shutil.copy2(f, dst)


setup(cffi_modules=["src/cranepredict/_build.py:ffibuilder"],
      cmdclass={"build_py": build_py_with_core},
      options={"bdist_wheel": {"py_limited_api": "cp310"}})
