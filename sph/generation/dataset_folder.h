#pragma once
// `spill-sim generate`'s dataset folder: the pipeline (generation.h) writing train.h5, valid.h5,
// test.h5 (one group per trajectory, "00000", "00001", ... within each file) and metadata.json.
//
// Each trajectory is first written to parts/ (its HDF5 file and a JSON of its parameters and
// statistics, each renamed into place when complete), so an interrupted generation resumes
// without redoing finished trajectories; parts/request.json holds the whole resolved request, and
// a folder is resumed only by the same one. The split files are assembled from the parts at the
// end. Shards of one request (GenerationShard) share the folder: each writes only its own
// trajectories' parts, and whichever finds every part finished assembles the splits (each
// process through temporaries of its own, so two doing it at once write the same files).

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "sph/generation/generation.h"

namespace sph {

// Returns metadata.json's content, or, for a shard while other shards' trajectories are missing,
// which are. Throws ConfigError for a bad scene or pointer or another request in the folder, or
// when assembling (options.shard.assemble_only) with trajectories missing (naming them),
// SimulationError for a failed run, RunInterrupted (frame_loop.h) when `stop` was set. A folder
// this call made is removed again when it fails before any trajectory is finished, unless it is
// a shard's.
GenerationResult generate_dataset(const GenerateOptions& options);

// The sink generate_dataset writes `folder` with: parts/ as the trajectories finish, the splits
// and metadata.json at the end. For a dataset written beside another sink's work (spill-train's
// --save-data tees it), into a folder of its own.
std::unique_ptr<TrajectorySink> dataset_folder_sink(const std::filesystem::path& folder);

// The request stored in `out_dir`/parts/request.json as options that assemble it
// (`spill-sim generate --assemble`). Throws ConfigError naming the file and key.
GenerateOptions stored_generation(const std::filesystem::path& out_dir);

// Writes a split file holding group "00000" of each of `parts` as groups 00000, 00001, ... in
// order, atomically (temp file + rename). Throws SimulationError naming the file.
void assemble_split(const std::filesystem::path& file,
                    const std::vector<std::filesystem::path>& parts);

}  // namespace sph
