// SPDX-License-Identifier: MIT
// Every benchmark's JSON context carries softbench's provenance (version, git revision, build
// type, compiler, CPU, threads) beside Google Benchmark's own, so two result files say which
// builds and machines they compare. Compiled into each benchmark executable: a static object's
// constructor runs before benchmark_main parses the command line.
#include "harness/provenance.h"

#include <benchmark/benchmark.h>

#include <string>

namespace {

struct ProvenanceContext {
  ProvenanceContext() {
    const nlohmann::json fields = softbench::harness::to_json(softbench::harness::provenance());
    for (const auto& [key, value] : fields.items()) {
      benchmark::AddCustomContext("softbench_" + key,
                                  value.is_string() ? value.get<std::string>() : value.dump());
    }
  }
};

const ProvenanceContext kContext;

}  // namespace
