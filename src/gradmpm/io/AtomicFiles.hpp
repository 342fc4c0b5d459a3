#pragma once
// The file-system steps that all-or-nothing outputs are made of, shared by the run folder
// (io/RunFolder.hpp) and the checkpoint folders (app/Checkpoint.hpp).
#include <filesystem>
#include <string>
#include <system_error>

namespace gradmpm {

/// Flushes a file or a folder (its entries) to disk; throws OutputError "`shown`: cannot flush to disk".
void fsync_path(const std::filesystem::path& p, const std::string& shown);

/// Makes `to` a hard link to the file `from`, or a copy where a link cannot be made
/// (another file system); returns the error of the copy, if any.
std::error_code link_or_copy(const std::filesystem::path& from, const std::filesystem::path& to);

/// `message` with every mention of the hidden path `hidden` (a staging folder, a
/// temporary) written as `shown`, the name the user knows.
std::string with_path_shown(std::string message, const std::filesystem::path& hidden, const std::string& shown);

/// Puts the complete folder `fresh` at `target` and removes what was there: one rename
/// when `target` does not exist, else one atomic swap (renameat2 RENAME_EXCHANGE) or, on
/// a file system without it, two renames through `aside` (target briefly absent).
/// Throws OutputError "`failure` (reason)".
void move_into_place(const std::filesystem::path& fresh, const std::filesystem::path& target,
                     const std::filesystem::path& aside, const std::string& failure);

}  // namespace gradmpm
