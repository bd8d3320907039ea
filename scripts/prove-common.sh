# The frame of the prove-*.sh scripts (sourced): a throwaway git worktree of HEAD in $tree, a
# check that a recipe changed exactly the files and lines it should, and a Release build of
# rodend there. Each script adds its catalogue line and code, then calls these.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
work=$(mktemp -d)
tree="$work/tree"
cleanup() {
  git -C "$repo" worktree remove --force "$tree" > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
git -C "$repo" worktree add --detach "$tree" HEAD > /dev/null
cd "$tree"

# prove_changed NAME "STATUS PATH"...: git status lists exactly these changes
prove_changed() {
  local name=$1
  shift
  local changed expected
  changed=$(git status --porcelain | sort)
  expected=$(printf '%s\n' "$@" | sort)
  echo "files the recipe touched:"
  echo "$changed"
  [ "$changed" = "$expected" ] || { echo "$name: expected exactly these changes: $expected" >&2; exit 1; }
}

# prove_lines NAME FILE ADDED REMOVED: the diff of FILE adds and removes these many lines
prove_lines() {
  local n
  n=$(git diff --numstat -- "$2" | awk '{print $1 "+" $2 "-"}')
  [ "$n" = "$3+$4-" ] || { echo "$1: $2 changed by $n lines, expected $3+$4-" >&2; exit 1; }
}

# prove_build: rodend, Release, warnings as errors (ccache when there is one)
prove_build() {
  local launcher=()
  export CCACHE_BASEDIR="$work"  # cache hits against other checkouts built the same way
  if command -v ccache > /dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRODEND_WERROR=ON -DRODEND_BUILD_TESTS=OFF \
    -DRODEND_BUILD_BENCHMARKS=OFF -DRODEND_PYTHON=OFF "${launcher[@]}" > /dev/null
  cmake --build build --target rodend -j"$(nproc)" > "$work/build.log" 2>&1 ||
    { tail -30 "$work/build.log"; exit 1; }
  echo "built rodend: $(grep -c 'Building CXX' "$work/build.log") C++ files compiled"
}
