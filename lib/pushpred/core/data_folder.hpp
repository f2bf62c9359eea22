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

/// Recordings (*.h5, *.json) below `folder`/`surface` (or below `folder` when surface is empty), sorted by name.
std::vector<std::filesystem::path> list_recordings(const std::filesystem::path& folder,
                                                   const std::string& surface = "");

}  // namespace pushpred
