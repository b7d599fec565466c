# Metadata lives in pyproject.toml; setup.py exists only because setuptools takes cffi_modules here.
# The extension is built for the stable ABI (cffi compiles it with Py_LIMITED_API; its file is
# _cranepredict.abi3.so), so one wheel per platform serves every CPython from 3.10 on.
from setuptools import setup

setup(cffi_modules=["src/cranepredict/_build.py:ffibuilder"],
      options={"bdist_wheel": {"py_limited_api": "cp310"}})
