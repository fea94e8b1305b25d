#!/usr/bin/env bash
# cmake --install into a fresh prefix, then, with nothing of the build or source tree in reach:
# the installed binary runs its default scene from its own share/dgmpm (outputs where it is run),
# prints its version, plots through the installed script; an example program outside the tree
# is built against the installed CMake package (find_package(dgmpm), dgmpm::dgmpm) and passes.
#   install_package.sh BUILD_DIR SOURCE_DIR WORK_DIR [PYTHON]
set -euo pipefail
build="$1" source="$2" work="$3" python="${4:-/usr/bin/python3}"
rm -rf "$work"
mkdir -p "$work/run"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
prefix="$work/prefix"
for f in bin/dgmpm include/dgmpm/dgmpm/stepper.hpp include/dgmpm/solver/simulation.hpp \
         include/dgmpm/stability/admissible_courant.hpp lib/cmake/dgmpm/dgmpmConfig.cmake \
         share/dgmpm/scenes/plate_impact.json share/dgmpm/reports/plot_fields_2d.py \
         share/dgmpm/examples/plot_run.py share/dgmpm/commit.txt; do
  [ -e "$prefix/$f" ] || { echo "not installed: $f" >&2; exit 1; }
done
# The installed binary must not read the source tree: its strings name no source path.
if grep -qF "$source" "$prefix/bin/dgmpm"; then
  echo "the installed binary holds the source path $source" >&2
  exit 1
fi
version="$("$prefix/bin/dgmpm" --version)"
[[ "$version" =~ ^dgmpm\ [0-9]+\.[0-9]+\.[0-9]+$ ]] || { echo "bad --version: $version" >&2; exit 1; }
# Default scene from the prefix, outputs in the working directory.
(cd "$work/run" && "$prefix/bin/dgmpm" run --json > summary.json)
grep -qF "\"scene\": \"$prefix/share/dgmpm/scenes/two_bar_impact.json\"" "$work/run/summary.json" \
  || { echo "the default scene did not come from the prefix" >&2; cat "$work/run/summary.json" >&2; exit 1; }
[ -f "$work/run/out/two_bar_impact/particles_000.csv" ] || { echo "no outputs in the working directory" >&2; exit 1; }
# The installed plotting example on a 1D and a 2D run (a scene of the prefix, --out elsewhere).
"$python" "$prefix/share/dgmpm/examples/plot_run.py" "$work/run/out/two_bar_impact" -o "$work/run/bar.png"
"$prefix/bin/dgmpm" run "$prefix/share/dgmpm/scenes/plate_impact.json" --out "$work/run/plate" >/dev/null
"$python" "$prefix/share/dgmpm/examples/plot_run.py" "$work/run/plate" -o "$work/run/plate.png"
[ -s "$work/run/bar.png" ] && [ -s "$work/run/plate.png" ] || { echo "no plot written" >&2; exit 1; }
# The outside example against the installed package.
cmake -S "$prefix/share/dgmpm/examples/library" -B "$work/example" \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/example" -j"$(nproc)" >/dev/null
"$work/example/plane_wave_example" --cells 16
echo "install and outside example: ok"
