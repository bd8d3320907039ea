#!/usr/bin/env bash
# Proves the subcommand recipe of docs/architecture.md: a new subcommand of `rodend` is one line
# of app/commands.def plus its function. In a throwaway git worktree of HEAD it adds
#   - the line RODEND_COMMAND(add_throwaway) at the end of app/commands.def and
#   - its function at the end of app/commands_catalogue.cpp (a subcommand "throwaway" with an
#     option --times N that prints "throwaway" N times),
# checks with git that nothing else changed, builds rodend there, and checks that the new
# subcommand runs, is listed by `rodend --help` with its help text, and that a bad value of its
# option is exit 2 like every other.
# Takes a few minutes without a warm ccache (a build of rodend); CTest runs it as prove.command
# (label `prove`). Exit 77 (skipped) outside a git checkout.
# Usage: bash scripts/prove-command.sh
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
git rev-parse --verify -q HEAD > /dev/null 2>&1 ||
  { echo "prove-command: not a git checkout with a commit (it works in a worktree of HEAD): skipped"; exit 77; }
work=$(mktemp -d)
tree="$work/tree"
cleanup() {
  git -C "$repo" worktree remove --force "$tree" > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
git worktree add --detach "$tree" HEAD > /dev/null
cd "$tree"

# 1. the subcommand: one catalogue line, and its function
echo 'RODEND_COMMAND(add_throwaway)' >> app/commands.def
cat > "$work/function.cpp" << 'CPP'
namespace rodend::cli {
void add_throwaway(CLI::App& app, Outcome&) {
  auto times = std::make_shared<int>(1);
  CLI::App* c = app.add_subcommand("throwaway", "A subcommand added by scripts/prove-command.sh.");
  c->add_option("--times", *times, "how many lines")->check(CLI::Range(1, 9));
  c->callback([times] {
    for (int i = 0; i < *times; ++i) std::cout << "throwaway\n";
  });
}
}  // namespace rodend::cli
CPP
cat "$work/function.cpp" >> app/commands_catalogue.cpp
n=$(git diff --numstat -- app/commands.def | awk '{print $1 "+" $2 "-"}')
[ "$n" = "1+0-" ] || { echo "prove-command: app/commands.def changed by $n lines, expected one added" >&2; exit 1; }
changed=$(git status --porcelain | sort)
expected=$(printf '%s\n' " M app/commands.def" " M app/commands_catalogue.cpp" | sort)
echo "files the recipe touched:"
echo "$changed"
[ "$changed" = "$expected" ] || { echo "prove-command: expected exactly: $expected" >&2; exit 1; }

# 2. build rodend
launcher=()
export CCACHE_BASEDIR="$work"
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRODEND_WERROR=ON -DRODEND_BUILD_TESTS=OFF \
  -DRODEND_BUILD_BENCHMARKS=OFF -DRODEND_PYTHON=OFF "${launcher[@]}" > /dev/null
cmake --build build --target rodend -j"${RODEND_JOBS:-$(nproc)}" > "$work/build.log" 2>&1 ||
  { tail -30 "$work/build.log"; exit 1; }

# 3. it runs, it is listed, its bad input is exit 2
out=$(./build/rodend throwaway --times 3)
[ "$out" = "$(printf 'throwaway\nthrowaway\nthrowaway')" ] ||
  { echo "prove-command: rodend throwaway --times 3 printed: $out" >&2; exit 1; }
./build/rodend --help | grep -q 'throwaway.*A subcommand added by scripts/prove-command.sh' ||
  { echo "prove-command: rodend --help does not list throwaway" >&2; exit 1; }
rc=0
./build/rodend throwaway --times 0 2> /dev/null || rc=$?
[ "$rc" = 2 ] || { echo "prove-command: rodend throwaway --times 0 exit $rc, expected 2" >&2; exit 1; }
echo "rodend throwaway --times 3: three lines; listed by --help; --times 0: exit 2"
echo "prove-command: ok"
