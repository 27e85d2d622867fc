#!/usr/bin/env bash
# run_tests.sh SOURCE_DIR BUILD_DIR -- the Python module's ctest (tests/python.cmake):
# builds and installs the module as the README says, into a venv of Debian's interpreter under
# the build tree (BUILD_DIR/python-venv; setuptools' objects in BUILD_DIR/python-build, so
# the source tree gets nothing), then runs tests/python with pytest from that venv (whose
# python is /usr/bin/python3 with Debian's packages).  Exit 77 (skipped) when a Debian package
# the test needs is really missing; it says which.
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(mkdir -p "$2" && cd "$2" && pwd)
py=/usr/bin/python3
missing=()
for mod in numpy setuptools pip venv pytest hypothesis scipy; do
  "$py" -c "import $mod" 2>/dev/null || missing+=("$mod")
done
if ((${#missing[@]})); then
  echo "python_module: SKIPPED: $py lacks ${missing[*]} (./dev setup installs python3-*)" >&2
  exit 77
fi
venv=$build/python-venv
[ -x "$venv/bin/python" ] || "$py" -m venv --system-site-packages "$venv"
export GTET_PY_BUILD_DIR=$build/python-build GTET_PY_WERROR=1
cd "$src"
echo "+ $venv/bin/pip install --no-build-isolation --no-index ." >&2
"$venv/bin/pip" install --no-build-isolation --no-index --no-deps --quiet --disable-pip-version-check .
# from the build tree, so that the source folder python/ is not what gets imported
cd "$build"
export PYTHONDONTWRITEBYTECODE=1
exec "$venv/bin/python" -m pytest -p no:cacheprovider -q -ra "$src/tests/python"
