#!/usr/bin/env bash
# No CGAL header is reachable from a public header of static_core/ or kinetic/: CGAL's types stay behind the
# internal/ headers, so the readers, shading, the CLI and any user of the engines compile without it.
# Usage: check_public_headers.sh CXX SOURCE_DIR
set -euo pipefail
cxx=$1
source_dir=$2
status=0
while IFS= read -r header; do
  dependencies=$("$cxx" -std=c++20 -I "$source_dir" -M -x c++ "$source_dir/$header")
  if grep -q '/CGAL/' <<<"$dependencies"; then
    echo "check_public_headers: $header includes CGAL (move the CGAL types behind an internal/ header)" >&2
    status=1
  fi
done < <(git -C "$source_dir" ls-files 'static_core/*.hpp' 'kinetic/*.hpp' ':!:*/internal/*')
exit "$status"
