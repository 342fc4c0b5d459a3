#pragma once
// The key tables of docs/case-files.md, rendered from the declarations (app/CaseKeys.cpp,
// each material's keys, each linear solver's doc). `gradmpm keys KIND` prints them;
// `gradmpm keys --update docs/case-files.md` (scripts/update-docs) writes them between the markers <!-- keys KIND -->
// and
// <!-- /keys --> of docs/case-files.md; tests/test_keys_doc.cpp fails when the
// checked-in file differs.
#include <filesystem>
#include <string>
#include <vector>

namespace gradmpm {

/// The kinds with a table set: "bar", "bar-mpm", "mpm".
std::vector<std::string> key_doc_kinds();

/// Markdown of every section of that kind; throws InputError for an unknown kind.
std::string keys_markdown(const std::string& kind);

/// `doc` with the region after each <!-- keys KIND --> marker (up to <!-- /keys -->)
/// replaced by keys_markdown(KIND). Throws std::runtime_error on an unclosed marker.
std::string with_generated_keys(const std::string& doc);

/// Rewrites the file `path` with_generated_keys (all or nothing); InputError if unreadable.
void update_generated_keys(const std::filesystem::path& path);

}  // namespace gradmpm
