// A command's --out-dir for the length of one run, so that what a run leaves there is one set:
// this run's files complete, or the previous run's untouched, never a mix of the two.
//
// While an OutputDir is open:
//  - it holds an exclusive lock on the folder: a second run into the same folder is refused
//    (InputError naming the first run's process id);
//  - SIGINT and SIGTERM are recorded for the run's loops to poll (core/interrupt.h);
//  - every OutputFile committed inside the folder is held back: its temporary stays hidden
//    beside its place (.NAME.tmpPID-N.EXT) until commit() puts all of them in place together
//    and removes what is left of the previous set among the entries the run owns.
// Closed without commit() (a failure, an interruption), it removes its temporaries and the
// empty folders it made: the folder keeps its previous set whole. Temporaries of a run that
// was killed outright (SIGKILL, power loss) are removed by the next run into the folder, once
// their process is gone. Only a kill during commit()'s renames (microseconds) can mix sets.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "osteon/core/error.h"

namespace osteon {
class InterruptScope;
}

namespace osteon::geometry {

class OutputDir {
 public:
  // Creates `folder` when missing, locks it and removes killed runs' temporaries in it (three
  // levels deep, as deep as commands write). `owned` names the entries of the folder (files, or
  // folders filled by the run alone) that make up a run's set: after commit(), they hold this run's
  // files only. Throws InputError naming the folder (after `option`, the command's name for it)
  // when it cannot be made or another run holds it. One OutputDir is open at a time in a process.
  explicit OutputDir(const std::string& folder, std::vector<std::string> owned = {},
                     const std::string& option = optionRef("outDir"));
  ~OutputDir();
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  const std::string& path() const { return folder_; }
  // Puts every held-back output in place and removes the rest of the previous set. Throws
  // Interrupted (nothing is put in place) when SIGINT or SIGTERM came, InputError when a
  // rename fails.
  void commit();

  // OutputFile::commit's hook: true when finalPath lies inside the open folder, which then
  // keeps tempPath until commit() (or removes it when closed without one).
  static bool holdBack(const std::string& tempPath, const std::string& finalPath);
  // Where the bytes of an output of this run are now: the held-back temporary of a path
  // committed inside the open folder, otherwise the path itself. For a run that reads back
  // what it wrote (force plots drawn from the force logs).
  static std::string currentPath(const std::string& path);

 private:
  void removeLeftovers() const;
  void removeStale() const;
  void removeEmptyFolders(bool includeOwnedRoots) const;

  std::string folder_;
  std::string option_;
  std::string root_;  // canonical
  std::vector<std::string> owned_;
  bool created_ = false;
  int lockFd_ = -1;
  bool committed_ = false;
  std::vector<std::pair<std::string, std::string>> held_;  // temporary, final (canonical)
  std::map<std::string, std::size_t> heldIndex_;           // final (canonical) -> held_
  std::unique_ptr<InterruptScope> interrupts_;
};

}  // namespace osteon::geometry
