#pragma once
// The text files a user writes for the shapes (docs/own-objects.md): shape files, and the CSV files of a shape table
// and of a polygon's outline. In a CSV file lines end in "\n" or "\r\n", and blank lines and lines starting with '#'
// are comments. Every error is an InputError naming the file (and the line).
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace pushpred {

/// The whole of the text file at `path`; `what` names it in an error ("a shape table"): a folder, or a file that
/// cannot be opened or read.
std::string read_text_file(const std::filesystem::path& path, const std::string& what);

/// Calls `row(line, where)` for each line of the CSV `text` that is neither blank nor a comment, its "\r" removed;
/// `where` is "SOURCE:N", N the line's number from 1.
void for_each_csv_row(const std::string& text, const std::string& source,
                      const std::function<void(const std::string& line, const std::string& where)>& row);

/// The vertices of an outline file (as the dataset's butter_outline.csv): rows x_m,y_m of two finite numbers
/// [m, body frame], after an optional header line starting with "x". Unchecked as a polygon.
std::vector<Eigen::Vector2d> read_outline_csv_vertices(const std::filesystem::path& path);

}  // namespace pushpred
