#pragma once
// Where the real MCube recordings are. The order is: an explicit folder (an app's --data flag), the environment
// variable PUSHPRED_DATA, the folder fixed at build time (../shared/data/mcube beside the source tree), and
// ../shared/data/mcube relative to the working directory.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pushpred {

/// The data folder to use; throws InputError naming every place tried when none exists.
std::filesystem::path resolve_data_folder(const std::optional<std::string>& explicit_folder = std::nullopt);
/// The data folder for a command that needs it only for some inputs (butter's outline, read from it): an explicit
/// folder must exist (InputError otherwise); without one, the default when there is one, else an empty path, so
/// that only an input that needs the folder fails, naming it.
std::filesystem::path data_folder_if_any(const std::optional<std::string>& explicit_folder = std::nullopt);

/// True for the recordings' extensions, .h5 and .json in any case (.H5, .Json).
bool has_recording_extension(const std::filesystem::path& path);

/// What makes two paths the same push: the device and inode of the file they reach (so hard links and symbolic
/// links to one file are one push), or, where the file cannot be stat'ed, its canonical path.
std::string file_identity(const std::filesystem::path& path);

/// Recordings (*.h5, *.json, any case) below `folder`/`surface` (or below `folder` when surface is empty), sorted by
/// name. Entries so named that are not regular files (a FIFO, a broken link, a link loop), and subfolders that cannot
/// be listed, are listed too, so that reading them fails by name; links to folders are not followed.
std::vector<std::filesystem::path> list_recordings(const std::filesystem::path& folder,
                                                   const std::string& surface = "");

}  // namespace pushpred
