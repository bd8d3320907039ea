// The case files of a run checked before its summary is written: each row's file is there and
// holds its case. A file's identity (device, inode, size, modification and change times) is
// noted when the run verifies or writes it; one whose identity changed is read again.
#include <sys/stat.h>

#include <algorithm>
#include <new>
#include <stdexcept>

#include "sweep/runner.hpp"

namespace rodend {
namespace fs = std::filesystem;

std::uint64_t case_file_stamp(const fs::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return 0;
  std::uint64_t h = 14695981039346656037ULL;  // FNV-1a over the fields
  for (const auto v :
       {static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino),
        static_cast<std::uint64_t>(st.st_size), static_cast<std::uint64_t>(st.st_mtim.tv_sec),
        static_cast<std::uint64_t>(st.st_mtim.tv_nsec),
        static_cast<std::uint64_t>(st.st_ctim.tv_sec),
        static_cast<std::uint64_t>(st.st_ctim.tv_nsec)})
    for (int b = 0; b < 64; b += 8) h = (h ^ ((v >> b) & 0xff)) * 1099511628211ULL;
  return h | 1;  // never 0 (unknown)
}

void note_case_file(const RunPlan& plan, std::size_t i, const std::string& id) {
  if (i < plan.stamps.size())
    plan.stamps[i] = std::max<std::uint64_t>(case_file_stamp(plan.cases_dir / (id + ".h5")), 2);
}

namespace {

/// Why the file of `row` (slot `slot`) cannot stand behind its summary row ("" when it can): it
/// is gone (deleted, or not a regular file: a link planted) or, its identity changed since its
/// case id was known to hold, it does not read as that case (another case's file copied or
/// renamed over it, damaged bytes).
std::string case_file_problem(const RunPlan& plan, std::size_t slot, const CaseRecord& row) {
  const fs::path f = plan.cases_dir / (row.id + ".h5");
  const std::uint64_t now = case_file_stamp(f);
  if (now == 0) return f.string() + ": gone (removed, or replaced by something else)";
  if (slot < plan.stamps.size() && plan.stamps[slot] == now) return "";
  try {
    if (!read_case_record_strict(f)) return f.string() + ": gone";
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

void check_case_files(const RunPlan& plan) {
  std::vector<CaseRecord> block;
  std::vector<std::string> bad;
  const std::size_t rows = plan.spool->size();
  // the rows come in slot order, and a slot has a row when it has a stamp (never 0 then)
  std::size_t slot = 0;
  for (std::size_t begin = 0; begin < rows; begin += 4096) {
    plan.spool->read(begin, std::min(rows, begin + 4096), block);
    for (const CaseRecord& r : block) {
      while (slot < plan.stamps.size() && plan.stamps[slot] == 0) ++slot;
      if (std::string why = case_file_problem(plan, slot, r); !why.empty())
        bad.push_back(std::move(why));
      ++slot;
    }
  }
  if (bad.empty()) return;
  std::string m = std::to_string(bad.size()) +
                  " case file(s) disappeared or were replaced during the run (by another "
                  "process); no summary written, it would list cases without their files:";
  for (std::size_t k = 0; k < bad.size() && k < 20; ++k) m += "\n  " + bad[k];
  if (bad.size() > 20) m += "\n  ...";
  throw std::runtime_error(m + "\nrodend: stopped: " + std::to_string(rows - bad.size()) + " of " +
                           std::to_string(plan.in_scope) + " case(s) complete in " +
                           plan.cases_dir.string() + ". Resume with: " + plan.resume +
                           " (it reruns the missing cases and lists the files that hold another "
                           "case)");
}

}  // namespace rodend
