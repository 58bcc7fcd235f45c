// `madsfm synth`: writes synthetic two-view pair directories (src/madsfm/synthetic) plus a pairs.txt,
// for `madsfm bench` and the benchmarks in docs/benchmarks.md.
#pragma once

namespace madsfm {

int RunSynth(int argc, char** argv);
// `madsfm synth_project`: a synthetic COLMAP project (database + depth sidecars), colmap_ext/synthetic.
int RunSynthProject(int argc, char** argv);

}  // namespace madsfm
