// Results writers: what a run writes per view besides results.csv, each setting the columns of
// the rows it wrote for (error maps: map; pictures: picture*, and the image metrics img_*). The
// runner hands every view to them (RunOptions::on_view) before its rows join the run.
//
// Adding a writer: one function `void NAME(const ViewWriteContext&, ViewOutput&)` (a file of its
// own when it is large), its columns in harness/metrics/columns.cpp, and one line in
// view_writers() (view_writers.cpp).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/experiment/experiment.h"
#include "harness/metrics/row.h"
#include "harness/run/runner.h"

namespace pxh {

// What a writer writes into: the run's partial folder (its files move with the folder when the
// run commits).
struct ViewWriteContext {
    const Experiment& ex;
    std::filesystem::path dir;
};

struct ViewWriter {
    const char* name;
    bool (*wanted)(const Experiment&);  // whether the run writes it at all
    void (*write)(const ViewWriteContext&, ViewOutput&);
};

// The registry, in the order they run: maps (--maps / maps = true), pictures ([render]).
const std::vector<ViewWriter>& view_writers();

// The writers the experiment wants (empty: the run needs no per-view callback).
std::vector<const ViewWriter*> wanted_view_writers(const Experiment& ex);
// RunOptions::on_view calling each of them per view, into the results folder `dir` (an empty
// function when the experiment wants none). `ex` must outlive it.
RunOptions::ViewHook view_writers_into(const Experiment& ex, const std::filesystem::path& dir);

// The truth's picture of a row's view: "truth_FIELD_tTHETA_pPHI[_dD_fF][_BASERr][_cutC].png"
// (a curved base and its radius; C: the row's [views] cut, whose plane the picture shows), safe
// characters.
std::string truth_picture_name(const ResultRow& r);

}  // namespace pxh
