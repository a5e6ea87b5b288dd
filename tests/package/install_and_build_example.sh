#!/usr/bin/env bash
# The installed CMake package as an integrator meets it: install osteon into a scratch
# prefix, configure examples/drill_minimal against that prefix only (find_package(osteon)),
# build it, run it, and check it drilled (a positive peak force). Fails when the export,
# the installed headers or a found-again dependency is broken.
#
# usage: install_and_build_example.sh CMAKE BUILD_DIR EXAMPLE_DIR WORK_DIR GENERATOR
#                                     BUILD_TYPE CXX_COMPILER [LAUNCHER]
set -euo pipefail
cmake_bin=$1 build_dir=$2 example_dir=$3 work_dir=$4 generator=$5 build_type=$6 cxx=$7
launcher=${8:-}

# A fresh scratch folder each run (kept on failure for a look; ccache keeps rebuilds quick).
rm -rf "$work_dir"
mkdir -p "$work_dir"
prefix="$work_dir/prefix"
example_build="$work_dir/build"

echo "== install $build_dir -> $prefix"
"$cmake_bin" --install "$build_dir" --prefix "$prefix" --config "$build_type" >"$work_dir/install.log"
for f in lib/cmake/osteon/osteonConfig.cmake lib/cmake/osteon/osteonConfigVersion.cmake \
         lib/cmake/osteon/osteonTargets.cmake bin/osteon \
         include/osteon/simulation/session.h include/osteon/geometry/hierarchy/dph_queries.inl; do
  [[ -e "$prefix/$f" ]] || { echo "FAIL: $f was not installed"; exit 1; }
done

# Every imported target the package links must resolve to a full path: a name left bare (a
# find_dependency missing from osteonConfig.cmake) becomes -l<name>, which may still link by
# luck on this machine (-lOpenMeshCore) and not on another. Only system libraries may be -l.
check_link_line() {
  local bare
  bare=$(cat "$1"/build.ninja "$1"/CMakeFiles/*.dir/link.txt 2>/dev/null \
         | grep -Eo -- '(^| )-l[^ ]+' | sed 's/^ //' | sort -u \
         | grep -Ev -- '^-l(dl|pthread|m|rt)$' || true)
  if [[ -n "$bare" ]]; then
    echo "FAIL: $2 links bare library names (targets the package did not find again): $bare"
    exit 1
  fi
}

echo "== configure $example_dir against $prefix"
args=(-S "$example_dir" -B "$example_build" -G "$generator"
      -DCMAKE_BUILD_TYPE="$build_type" -DCMAKE_CXX_COMPILER="$cxx"
      -DCMAKE_PREFIX_PATH="$prefix"
      -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON
      -DCMAKE_FIND_PACKAGE_NO_SYSTEM_PACKAGE_REGISTRY=ON
      -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
[[ -n "$launcher" ]] && args+=(-DCMAKE_CXX_COMPILER_LAUNCHER="$launcher")
"$cmake_bin" "${args[@]}" >"$work_dir/configure.log" 2>&1 \
  || { cat "$work_dir/configure.log"; echo "FAIL: configuring the example"; exit 1; }

# The package must be the one just installed, and nothing may point back at the sources.
found_dir=$(sed -n 's/^osteon_DIR:PATH=//p' "$example_build/CMakeCache.txt")
if [[ "$(realpath "$found_dir")" != "$(realpath "$prefix/lib/cmake/osteon")" ]]; then
  echo "FAIL: find_package(osteon) used $found_dir, not $prefix/lib/cmake/osteon"; exit 1
fi
src_root=$(realpath "$example_dir/../..")
if grep -Eq -- "(-I|-isystem )$src_root/[^/ ]+/include" "$example_build/compile_commands.json"; then
  echo "FAIL: the example's include paths reach into a module of the source tree $src_root:"
  cat "$example_build/compile_commands.json"; exit 1
fi

echo "== build"
"$cmake_bin" --build "$example_build" --config "$build_type" >"$work_dir/build.log" 2>&1 \
  || { cat "$work_dir/build.log"; echo "FAIL: building the example"; exit 1; }
check_link_line "$example_build" "the example"

echo "== run"
out=$("$example_build/drill_minimal")
echo "$out"
peak=$(sed -n 's/^peak force: \([0-9.eE+-]*\) N$/\1/p' <<<"$out")
removed=$(sed -n 's/^removed volume: \([0-9.eE+-]*\) mm^3$/\1/p' <<<"$out")
[[ -n "$peak" && -n "$removed" ]] || { echo "FAIL: no peak force or removed volume printed"; exit 1; }
awk -v p="$peak" 'BEGIN { exit !(p > 0) }' || { echo "FAIL: peak force $peak N is not positive"; exit 1; }

# Every exported target, linked and used: the example needs only osteon::simulation, and a
# broken link interface (validation's CGAL, osteon::image) shows only in a program that uses it.
echo "== every exported target"
all_src="$work_dir/all"
mkdir -p "$all_src"
cat >"$all_src/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.20)
project(osteon_all_targets LANGUAGES CXX)
find_package(osteon REQUIRED)
add_executable(all_targets main.cpp)
target_link_libraries(all_targets PRIVATE osteon::core osteon::geometry osteon::simulation
                                          osteon::validation osteon::devices osteon::image)
CMAKE
cat >"$all_src/main.cpp" <<'CPP'
#include "osteon/devices/devices.h"
#include "osteon/validation/library_versions.h"
#include "osteon/validation/mesh_checks.h"
#include <cstdio>
int main() {
  osteon::geometry::TriangleMesh tetrahedron;
  tetrahedron.positionsMm = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const bool crossing = osteon::validation::doesSelfIntersect(tetrahedron);  // CGAL
  for (const auto& [name, version] : osteon::validation::libraryVersions())  // the plugin
    std::printf("%s %s\n", name.c_str(), version.c_str());
  std::printf("devices %d self-intersecting %d\n", osteon::devices::kInterfaceVersion, crossing);
  return crossing ? 1 : 0;
}
CPP
args[1]="$all_src"
args[3]="$work_dir/all-build"
"$cmake_bin" "${args[@]}" >"$work_dir/all-configure.log" 2>&1 \
  || { cat "$work_dir/all-configure.log"; echo "FAIL: configuring against every target"; exit 1; }
"$cmake_bin" --build "$work_dir/all-build" --config "$build_type" >"$work_dir/all-build.log" 2>&1 \
  || { cat "$work_dir/all-build.log"; echo "FAIL: building against every target"; exit 1; }
check_link_line "$work_dir/all-build" "the every-target program"
# The installed plugin, not the build tree's (the loader would try that one first).
all_out=$(OSTEON_IMAGE_PLUGIN="$prefix/lib/libosteon_image.so" "$work_dir/all-build/all_targets") \
  || { echo "$all_out"; echo "FAIL: the every-target program failed"; exit 1; }
echo "$all_out"
grep -qi "OpenImageIO" <<<"$all_out" || { echo "FAIL: the installed image plugin was not used"; exit 1; }

"$prefix/bin/osteon" --help >/dev/null || { echo "FAIL: the installed osteon does not run"; exit 1; }
rm -rf "$work_dir"
echo "PASS: installed package builds and runs examples/drill_minimal (peak force $peak N)"
