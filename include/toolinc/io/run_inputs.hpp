// The files and folders one run has read. Inputs are never modified: an output that resolves to one of
// them (the same path once normalised and links resolved, or the same file by device and inode), or
// that lies inside an input folder such as a session, is refused before anything is written.
#pragma once

#include <string>
#include <vector>

namespace toolinc {

// Starts the tracking (Command::run, for every executable). A program that reads and rewrites its own
// files, such as a test runner, does not call it, and then nothing is noted or refused.
void track_inputs();

// Called by the bounded reader for every file it opens, and by read_session for the session's folder.
void note_input(const std::string& path);
void note_input_folder(const std::string& dir);

// Throws InputError(output, "is an input of this run ...") when output would replace an input; "-"
// (standard output) never does.
void check_not_an_input(const std::string& output);
// The same comparison against files named on the command line, before any is read: throws
// InputError(output, "is also given as ...") when output is one of them.
void check_not_among(const std::string& output, const std::vector<std::string>& files);

// path made absolute and normal, with its links resolved as far as it exists.
std::string resolved_path(const std::string& path);
// Whether path, links resolved, is folder or lies inside it (links resolved too).
bool resolves_inside(const std::string& path, const std::string& folder);

// The files noted so far, as given, in the order read (so that a method failure can name its input).
std::vector<std::string> run_inputs();

}  // namespace toolinc
