# The frame of the prove scripts (scripts/prove-*.sh; sourced by each). A prove script shows that
# a recipe of docs/architecture.md holds: adding a thing of some kind touches one catalogue line
# plus the code that computes it, and nothing else, and the thing then arrives everywhere things
# of its kind go. A script defines two functions and ends with `prove_main`:
#   recipe  adds the thing in $tree (a git worktree of HEAD) and checks with prove_lines and
#           prove_changed that it touched exactly those files and lines;
#   check   after the build ($tree/build: rodend and the Python module), shows the thing
#           everywhere it should appear; scratch files go in $work.
# Alone (`bash scripts/prove-record.sh`, say) a script makes its own throwaway worktree, runs its recipe,
# builds, and runs its check. `bash scripts/prove.sh` runs every recipe in one worktree, each
# committed there before the next (so each is still checked alone), builds once, then runs every
# check: one build instead of one per script (CTest: `prove`, label prove).
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
prove_name=$(basename "$0" .sh)
if [ -n "${PROVE_TREE:-}" ]; then  # under scripts/prove.sh: its worktree, a folder per script
  tree=$PROVE_TREE
  work="$PROVE_WORK/$prove_name"
  mkdir -p "$work"
else
  git -C "$repo" rev-parse --verify -q HEAD > /dev/null 2>&1 ||
    { echo "$prove_name: not a git checkout with a commit (it works in a worktree of HEAD): skipped"; exit 77; }
  work=$(mktemp -d)
  tree="$work/tree"
  prove_cleanup() {
    git -C "$repo" worktree remove --force "$tree" > /dev/null 2>&1 || true
    rm -rf "$work"
  }
  trap prove_cleanup EXIT
  git -C "$repo" worktree add --detach "$tree" HEAD > /dev/null
fi
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

# prove_generated NAME: runs scripts/gen-docs.sh with the new build; it may rewrite only the
# files it generates (the recipe's own files are staged first, so they do not count)
prove_generated() {
  git add -A > /dev/null
  RODEND=./build/rodend bash scripts/gen-docs.sh > /dev/null
  local f generated
  generated=$(git diff --name-only | sort)
  echo "files scripts/gen-docs.sh regenerated: $(echo $generated)"
  for f in $generated; do
    case "$f" in
      docs/signals.md | docs/metrics.md | docs/choices.md | docs/studies.md | docs/results.md | \
        python/rodend/analysis/catalogue.py) ;;
      *) echo "$1: gen-docs.sh changed $f, which is not a generated file" >&2; exit 1 ;;
    esac
  done
}

# prove_build: rodend and the Python module, Release, warnings as errors (ccache when there is one)
prove_build() {
  local launcher=()
  export CCACHE_BASEDIR="$tree"  # cache hits against other checkouts built the same way
  if command -v ccache > /dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  fi
  # no link-time optimisation of the Python module (pybind11's default): the checks need it to
  # work, not to be fast, and its link is the slowest step of the build
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRODEND_WERROR=ON -DRODEND_BUILD_TESTS=OFF \
    -DRODEND_BUILD_BENCHMARKS=OFF -DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF "${launcher[@]}" > /dev/null
  cmake --build build --target rodend _rodend -j"${RODEND_JOBS:-$(nproc)}" > "$work/build.log" 2>&1 ||
    { tail -30 "$work/build.log"; exit 1; }
  echo "built rodend and _rodend: $(grep -c 'Building CXX' "$work/build.log") C++ files compiled"
}

# prove_main: what the script does, by the phase scripts/prove.sh asks for (alone: all of it)
prove_main() {
  case "${PROVE_PHASE:-alone}" in
    alone)
      recipe
      prove_build
      check
      ;;
    recipe)
      recipe
      git add -A
      git -c user.name=prove -c user.email=prove@localhost commit -q -m "recipe of $prove_name"
      ;;
    check) check ;;
    *) echo "$prove_name: unknown PROVE_PHASE ${PROVE_PHASE}" >&2; exit 2 ;;
  esac
}
