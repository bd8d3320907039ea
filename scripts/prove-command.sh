#!/usr/bin/env bash
# Proves the subcommand recipe of docs/architecture.md: a new subcommand of `rodend` is one line
# of app/commands.def plus its function. In a throwaway git worktree of HEAD it adds
#   - the line RODEND_COMMAND(add_throwaway) at the end of app/commands.def and
#   - its function at the end of app/commands_catalogue.cpp (a subcommand "throwaway" with an
#     option --times N that prints "throwaway" N times),
# checks with git that nothing else changed, builds rodend there, and checks that the new
# subcommand runs, is listed by `rodend --help` with its help text, and that a bad value of its
# option is exit 2 like every other.
# Takes a few minutes without a warm ccache (a build of rodend); scripts/prove.sh runs it with the others (CTest: prove)
# (label `prove`). Exit 77 (skipped) outside a git checkout.
# Usage: bash scripts/prove-command.sh
source "$(dirname "$0")/prove-common.sh"

recipe() {
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
prove_lines prove-command app/commands.def 1 0
prove_changed prove-command " M app/commands.def" " M app/commands_catalogue.cpp"

# 2. build rodend
}

check() {

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
}

prove_main
