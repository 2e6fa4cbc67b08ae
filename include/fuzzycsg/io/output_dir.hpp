#pragma once
// A verb's output folder replaced as a set: every file of a run written into a temporary folder
// beside it, synced, then exchanged with the folder in one rename (Linux's renameat2
// RENAME_EXCHANGE), so that a reader, a kill or a full disk never leaves old and new files
// mixed or half a set. The old set is then removed.
//
// Only a folder that is absent, empty or holds nothing but files of the set (an earlier run's)
// is replaced: one holding anything else is refused before any work, so that `-o ~/Desktop`
// deletes nothing that the program did not write. Temporary folders that killed runs left
// beside it are removed by the next run.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace fuzzycsg::io {

class OutputDir {
 public:
  // `names`: every file a run of the verb may write into the folder.
  OutputDir(std::filesystem::path dir, std::vector<std::string> names);

  // Throws InputError naming the folder when it cannot be the output: a file is at its path,
  // it holds something that is not one of `names`, or its parent cannot be written. Call it
  // before the work; commit() checks again.
  void check() const;

  // One file of the set (a name given to the constructor).
  void add(const std::string& name, std::string bytes);

  // Writes the set and puts it in the folder's place. InputError naming the folder (and the
  // reason) when it cannot; nothing is then changed.
  void commit();

  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::vector<std::string> names_;
  std::vector<std::pair<std::string, std::string>> files_;
};

}  // namespace fuzzycsg::io
