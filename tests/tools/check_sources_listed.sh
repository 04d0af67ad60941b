#!/usr/bin/env bash
# Every .cpp the repository tracks is compiled by some target of the build (CMake's source lists are explicit,
# so a new file that no list names would otherwise go unbuilt and untested). The fuzz harnesses are built in
# their own tree (PLEAT_FUZZ), the installed-tree consumer by its own project (install.consumer): both are left out.
# Files this configuration leaves out (cli/world_mpi.cpp without MPI) follow, relative to SOURCE_DIR.
# Usage: check_sources_listed.sh SOURCE_DIR BUILD_DIR/compile_commands.json [LEFT_OUT...]
set -euo pipefail
source_dir=$1
compile_commands=$2
shift 2
left_out=" $* "
missing=0
while IFS= read -r file; do
  [[ $left_out == *" $file "* ]] && continue
  if ! grep -qF "\"file\": \"$source_dir/$file\"" "$compile_commands"; then
    echo "check_sources_listed: $file is in no target's source list (CMakeLists.txt)" >&2
    missing=1
  fi
done < <(git -C "$source_dir" ls-files '*.cpp' ':!:tests/fuzz/*' ':!:tests/install/*')
exit "$missing"
