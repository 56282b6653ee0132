#include "harness/run/merge.h"

#include <tbb/info.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/core/safe_files.h"
#include "harness/core/sha256.h"
#include "harness/results/csv_table.h"
#include "harness/results/provenance.h"
#include "harness/results/results.h"
#include "harness/results/run_folder.h"
#include "harness/run/run_record.h"

namespace fs = std::filesystem;

namespace pxh {
namespace {

// One slice as read: its folder, run.json, and run.json's shard record.
struct SliceIn {
    std::string dir;
    nlohmann::json run, shard;
    std::string run_json_sha256;
};

std::string short_text(const nlohmann::json& v) {
    std::string s = v.is_string() ? v.get<std::string>() : v.dump();
    return s.size() > 80 ? s.substr(0, 77) + "..." : s;
}

SliceIn read_slice(const std::string& dir) {
    SliceIn s;
    s.dir = dir;
    std::error_code ec;
    const fs::file_status st = fs::status(dir, ec);
    if (fs::exists(st) && !fs::is_directory(st))
        throw InputError(dir, fs::is_regular_file(st)
                                  ? "is a file, not a slice's results folder"
                                  : "is not a folder (a FIFO, socket or device?), not a slice's "
                                    "results folder");
    try {
        std::cout << verify_results_folder(dir, false) << "\n";  // InputError unless intact
    } catch (const InputError& e) {
        // merge joins slices only as their runs wrote them: it has no --accept-edited.
        std::string what = e.what();
        const std::string offer = "pass --accept-edited to use them anyway";
        if (const size_t at = what.find(offer); at != std::string::npos)
            what.replace(at, offer.size(),
                         "pxh merge joins only intact slices: run that slice again");
        throw InputError("", what);
    }
    const fs::path run_json = fs::path(dir) / "run.json";
    const std::string text = read_regular_file(run_json.string());
    s.run_json_sha256 = sha256_hex(text);
    s.run = parse_run_record(text, run_json.string());
    s.shard = shard_record_of(s.run, run_json.string(), dir);
    return s;
}

std::string shard_text(const SliceIn& s) {
    return std::to_string(s.shard["index"].get<size_t>()) + "/" +
           std::to_string(s.shard["count"].get<size_t>());
}

// The inputs: the experiment and every height-field file with its sha256 (an edited file
// between slices, the TOML unchanged), each plug-in shader's sha256 and the tracers' paths
// (PXH_TRACER_PATH, Embree's ISA: the numbers depend on them); `b` against the first slice `a`.
void check_same_inputs(const SliceIn& a, const SliceIn& b) {
    const nlohmann::json none = "none";
    const auto inputs = [&](const SliceIn& s) {
        std::map<std::string, nlohmann::json> m;  // what -> its record
        if (s.run.contains("inputs") && s.run["inputs"].is_array())
            for (const auto& i : s.run["inputs"])
                if (i.is_object())
                    m[i.contains("heightfield")
                          ? "height-field file " + short_text(i.value("path", nlohmann::json("")))
                          : "experiment"] = i.value("sha256", none);
        if (s.run.contains("plugin_shaders") && s.run["plugin_shaders"].is_array())
            for (const auto& p : s.run["plugin_shaders"])
                if (p.is_object())
                    m["plug-in shader " + short_text(p.value("path", nlohmann::json(""))) +
                      " (method " + short_text(p.value("method", nlohmann::json(""))) + ")"] =
                        p.value("sha256", none);
        return m;
    };
    const auto ia = inputs(a), ib = inputs(b);
    for (const auto* m : {&ia, &ib})
        for (const auto& [what, v] : *m) {
            const auto x = ia.find(what), y = ib.find(what);
            const nlohmann::json va = x == ia.end() ? none : x->second;
            const nlohmann::json vb = y == ib.end() ? none : y->second;
            if (va != vb)
                throw InputError(b.dir, "ran with another " + what + ": sha256 " +
                                            short_text(vb).substr(0, 12) + " where " + a.dir +
                                            " has " + short_text(va).substr(0, 12) +
                                            " (an input changed between the slices: run every "
                                            "slice again with the same inputs)");
        }
    const nlohmann::json ta = a.run.value("tracers", none), tb = b.run.value("tracers", none);
    if (ta != tb) {
        std::string what = "tracers " + short_text(tb);
        if (ta.is_object() && tb.is_object())
            for (const auto& [k, v] : ta.items())
                if (!tb.contains(k) || tb[k] != v) {
                    what = k + " " + short_text(tb.value(k, none)) + " where " + a.dir + " has " +
                           short_text(v);
                    break;
                }
        throw InputError(b.dir, "ran its ground truths on another tracer path: " + what +
                                    " (the numbers depend on it: run every slice with the same "
                                    "PXH_TRACER_PATH on CPUs with the same vector units)");
    }
}

// The refusals: `b` against the first slice `a`, each one line naming `b`.
void check_same_run(const SliceIn& a, const SliceIn& b) {
    const auto& sa = a.shard;
    const auto& sb = b.shard;
    if (sa["experiment_sha256"] != sb["experiment_sha256"])
        throw InputError(
            b.dir,
            "is a slice of another experiment: " + short_text(b.run.value("experiment_file", "")) +
                " (sha256 " + short_text(sb["experiment_sha256"]).substr(0, 12) + ") where " +
                a.dir + " ran " + short_text(a.run.value("experiment_file", "")) + " (sha256 " +
                short_text(sa["experiment_sha256"]).substr(0, 12) + ")");
    const auto& ba = sa["build"];
    const auto& bb = sb["build"];
    if (ba.value("pxh_version", "") != bb.value("pxh_version", ""))
        throw InputError(b.dir, "was run by another pxh version: " +
                                    short_text(bb.value("pxh_version", "")) + " where " + a.dir +
                                    " was run by " + short_text(ba.value("pxh_version", "")));
    for (const auto& [k, v] : ba.items())
        if (!bb.contains(k) || bb[k] != v)
            throw InputError(
                b.dir, "was run by another build of pxh: " + k + " " +
                           short_text(bb.contains(k) ? bb[k] : nlohmann::json("none")) + " where " +
                           a.dir + " has " + short_text(v));
    // Each backend's facts (the GLSL backend's: its GL context, renderer and driver).
    const auto facts = [](const SliceIn& s, const std::string& name) {
        const nlohmann::json none = "none";
        if (!s.run.contains("backends") || !s.run["backends"].is_object()) return none;
        const auto& blocks = s.run["backends"];
        return blocks.contains(name) && blocks[name].is_object() ? blocks[name].value("facts", none)
                                                                 : none;
    };
    std::set<std::string> names;
    for (const SliceIn* s : {&a, &b})
        if (s->run.contains("backends") && s->run["backends"].is_object())
            for (const auto& [name, block] : s->run["backends"].items()) names.insert(name);
    for (const std::string& name : names)
        if (facts(a, name) != facts(b, name))
            throw InputError(b.dir, "ran its " + name +
                                        " rows on another setup: " + short_text(facts(b, name)) +
                                        " where " + a.dir + " has " + short_text(facts(a, name)));
    check_same_inputs(a, b);
    for (const auto& [k, v] : sa["selection"].items())
        if (!sb["selection"].contains(k) || sb["selection"][k] != v)
            throw InputError(b.dir, "is a slice of another selection of the experiment: " + k +
                                        " " +
                                        short_text(sb["selection"].value(k, nlohmann::json())) +
                                        " where " + a.dir + " has " + short_text(v));
    if (sa["partition"] != sb["partition"] || sa["count"] != sb["count"] ||
        sa["units_total"] != sb["units_total"])
        throw InputError(b.dir, "is cut another way: shard " + shard_text(b) + " of " +
                                    short_text(sb["units_total"]) + " units (" +
                                    short_text(sb["partition"]) + ") where " + a.dir +
                                    " is shard " + shard_text(a) + " of " +
                                    short_text(sa["units_total"]) + " units");
}

// Each backend's compiled shader sources (name -> sha256; a slice compiles only what its rows
// ran): one source under two hashes (a shader file under --shader-dir edited between slices) is
// refused, naming both slices.
void check_same_sources(const std::vector<SliceIn>& slices) {
    std::map<std::pair<std::string, std::string>, std::pair<nlohmann::json, std::string>> seen;
    for (const SliceIn& s : slices) {
        if (!s.run.contains("backends") || !s.run["backends"].is_object()) continue;
        for (const auto& [name, b] : s.run["backends"].items()) {
            if (!b.is_object() || !b.contains("sources") || !b["sources"].is_object()) continue;
            for (const auto& [src, sha] : b["sources"].items()) {
                const auto [it, fresh] =
                    seen.emplace(std::make_pair(name, src), std::make_pair(sha, s.dir));
                if (!fresh && it->second.first != sha)
                    throw InputError(s.dir, "compiled another " + name + " source " + src +
                                                ": sha256 " + short_text(sha).substr(0, 12) +
                                                " where " + it->second.second + " has " +
                                                short_text(it->second.first).substr(0, 12) +
                                                " (a shader changed between the slices: run "
                                                "every slice again with the same shaders)");
            }
        }
    }
}

bool same_number(double a, double b) {
    return a == b || std::fabs(a - b) <= 1e-9 * std::max(std::fabs(a), std::fabs(b));
}

// The rows of one unit, checked against what the slice's run.json says the unit is.
struct UnitRows {
    const SliceIn* slice = nullptr;
    std::vector<std::vector<std::string>> rows;
};

void check_unit_rows(const CsvTable& t, size_t first, const nlohmann::json& u) {
    const size_t n = u["rows"].get<size_t>();
    const auto& thetas = u["theta_deg"];
    if (thetas.empty() || n % thetas.size() != 0)
        throw InputError(t.path, "run.json's unit " + u["unit"].dump() + " records " +
                                     std::to_string(n) + " rows for " +
                                     std::to_string(thetas.size()) + " views");
    const size_t per_view = n / thetas.size();
    for (size_t k = 0; k < n; ++k) {
        const size_t r = first + k;
        const double theta = thetas[k / per_view].get<double>();
        const bool ok = t.get(r, "heightfield") == u["heightfield"].get<std::string>() &&
                        same_number(t.number(r, "scale"), u["scale"].get<double>()) &&
                        same_number(t.number(r, "bias"), u["bias"].get<double>()) &&
                        same_number(t.number(r, "phi_deg"), u["phi_deg"].get<double>()) &&
                        same_number(t.number(r, "theta_deg"), theta);
        if (!ok)
            throw InputError(t.where(r), "row is not of unit " + u["unit"].dump() + " (" +
                                             u["heightfield"].get<std::string>() + " phi " +
                                             u["phi_deg"].dump() + " theta " +
                                             format_number(theta) + ") as run.json records");
    }
}

nlohmann::json slice_provenance(const SliceIn& s) {
    nlohmann::json units = nlohmann::json::array();
    for (const auto& u : s.shard["units"]) units.push_back(u["unit"]);
    nlohmann::json p = {{"dir", fs::absolute(s.dir).lexically_normal().string()},
                        {"shard", shard_text(s)},
                        {"run_json_sha256", s.run_json_sha256},
                        {"units", units},
                        {"cost", s.shard.value("cost", 0.0)}};
    for (const char* k : {"host", "cpu_model", "threads", "date_utc", "seconds", "rows",
                          "failed_rows", "command_line", "git_commit", "pxh_version"})
        if (s.run.contains(k)) p[k] = s.run[k];
    // What a backend's block records of the slice's own process (llvmpipe's threads).
    if (s.run.contains("backends") && s.run["backends"].is_object())
        for (const auto& [name, block] : s.run["backends"].items())
            if (block.is_object() && block.contains("LP_NUM_THREADS"))
                p["LP_NUM_THREADS"] = block["LP_NUM_THREADS"];
    return p;
}

using ByIndex = std::map<size_t, const SliceIn*>;

// Every shard 0..N-1 exactly once: the slices by index.
ByIndex check_complete(const std::vector<SliceIn>& slices) {
    const size_t count = slices[0].shard["count"].get<size_t>();
    ByIndex by_index;
    for (const auto& s : slices) {
        const size_t i = s.shard["index"].get<size_t>();
        if (by_index.count(i))
            throw InputError(s.dir,
                             "overlaps " + by_index[i]->dir + ": both are shard " + shard_text(s));
        by_index[i] = &s;
    }
    std::string missing;
    for (size_t i = 0; i < count; ++i)
        if (!by_index.count(i))
            missing += (missing.empty() ? "" : "; ") + std::string("shard ") + std::to_string(i) +
                       "/" + std::to_string(count) + " missing";
    if (!missing.empty())
        throw InputError("merge", missing + " (slices given: " + std::to_string(slices.size()) +
                                      " of " + std::to_string(count) + ")");
    return by_index;
}

// The rows of every unit, each unit from exactly one slice.
struct Gathered {
    std::vector<UnitRows> units;
    std::vector<std::string> header;
    size_t rows = 0, failed = 0;
};

Gathered gather_rows(const ByIndex& by_index, size_t units_total) {
    Gathered g;
    g.units.resize(units_total);
    for (const auto& [index, s] : by_index) {
        const std::string csv = (fs::path(s->dir) / "results.csv").string();
        const CsvTable t = read_csv(csv);
        if (g.header.empty()) g.header = t.columns;
        if (t.columns != g.header)
            throw InputError(csv, "has other columns than the first slice's results.csv");
        size_t next = 0;
        for (const auto& u : s->shard["units"]) {
            const size_t k = u.value("unit", units_total);
            if (k >= units_total || !u.contains("rows") || !u["rows"].is_number_unsigned())
                throw InputError(s->dir, "run.json records a malformed unit: " + short_text(u));
            if (g.units[k].slice)
                throw InputError(s->dir, "overlaps " + g.units[k].slice->dir + ": both ran unit " +
                                             std::to_string(k) + " (" +
                                             short_text(u.value("heightfield", "")) + ")");
            const size_t n = u["rows"].get<size_t>();
            if (next + n > t.rows.size())
                throw InputError(csv, std::to_string(t.rows.size()) +
                                          " rows, fewer than run.json's units record");
            check_unit_rows(t, next, u);
            g.units[k].slice = s;
            g.units[k].rows.assign(t.rows.begin() + long(next), t.rows.begin() + long(next + n));
            next += n;
        }
        if (next != t.rows.size())
            throw InputError(csv, std::to_string(t.rows.size()) +
                                      " rows, run.json's units record " + std::to_string(next));
        const int status = t.index("status");
        for (const auto& r : t.rows) g.failed += status >= 0 && r[size_t(status)] != "ok";
        g.rows += t.rows.size();
    }
    for (size_t k = 0; k < units_total; ++k)
        if (!g.units[k].slice)
            throw InputError("merge", "unit " + std::to_string(k) + " of " +
                                          std::to_string(units_total) +
                                          " is in no slice (the slices do not cover the run)");
    return g;
}

std::string merged_csv(const Gathered& g) {
    std::string text;
    for (size_t c = 0; c < g.header.size(); ++c) text += (c ? "," : "") + csv_quote(g.header[c]);
    text += "\n";
    for (const auto& u : g.units)
        for (const auto& r : u.rows) {
            for (size_t c = 0; c < r.size(); ++c) text += (c ? "," : "") + csv_quote(r[c]);
            text += "\n";
        }
    return text;
}

// The slices' other files (maps, pictures), named by the whole run's row index already;
// returns how many.
size_t copy_files(const ByIndex& by_index, const fs::path& tmp) {
    std::map<std::string, std::string> copied;  // relative path -> slice
    for (const auto& [index, s] : by_index)
        for (const auto& [rel, rec] : s->run["files"].items()) {
            if (rel == "results.csv") continue;
            const fs::path rp = fs::path(rel).lexically_normal();
            if (rp.is_absolute() || rp.empty() || *rp.begin() == "..")
                throw InputError((fs::path(s->dir) / "run.json").string(),
                                 "records a file outside its folder: " + rel);
            if (copied.count(rel))
                throw InputError((fs::path(s->dir) / rel).string(),
                                 "is also in " + copied[rel] + ": the slices overlap");
            copied[rel] = s->dir;
            fs::create_directories((tmp / rp).parent_path());
            copy_to_new_file(fs::path(s->dir) / rp, tmp / rp);
        }
    return copied.size();
}

// OUT's run.json (less its files record): the slices' experiment and GL record, the merge's
// own provenance, and the slices' provenance.
nlohmann::json merged_record(const SliceIn& first, const ByIndex& by_index, const Gathered& g,
                             const std::string& command_line, double merge_seconds) {
    nlohmann::json run = provenance(int(tbb::info::default_concurrency()));
    run["command_line"] = command_line;
    for (const char* k : {"experiment_file", "experiment", "experiment_name", "inputs", "warnings",
                          "plugin_shaders", "backends", "tracers"})
        if (first.run.contains(k)) run[k] = first.run[k];
    double seconds = 0;
    nlohmann::json from = nlohmann::json::array();
    for (const auto& [index, s] : by_index) {
        // Each backend's sources: every slice's (a slice compiles only what its rows ran).
        if (run.contains("backends") && run["backends"].is_object() &&
            s->run.contains("backends") && s->run["backends"].is_object())
            for (const auto& [name, b] : s->run["backends"].items())
                if (run["backends"].contains(name) && b.is_object() && b.contains("sources") &&
                    b["sources"].is_object())
                    for (const auto& [k, v] : b["sources"].items())
                        run["backends"][name]["sources"][k] = v;
        seconds += s->run.value("seconds", 0.0);
        from.push_back(slice_provenance(*s));
    }
    run["rows"] = g.rows;
    run["failed_rows"] = g.failed;
    run["seconds"] = seconds;  // the slices' run times added up
    run["merged"] = {{"count", first.shard["count"]},
                     {"partition", first.shard["partition"]},
                     {"units_total", first.shard["units_total"]},
                     {"experiment_sha256", first.shard["experiment_sha256"]},
                     {"selection", first.shard["selection"]},
                     {"build", first.shard["build"]},
                     {"merge_seconds", merge_seconds},
                     {"slices", from}};
    return run;
}

}  // namespace

int merge_slices(const MergeRequest& a, const std::string& command_line) {
    const auto t0 = std::chrono::steady_clock::now();
    if (a.out.empty()) throw InputError("merge", "the output folder OUT is an empty path");
    for (const auto& d : a.dirs)
        if (d.empty()) throw InputError("merge", "a slice's folder is an empty path");
    std::error_code ec;
    const fs::path out_abs = fs::weakly_canonical(fs::absolute(a.out), ec);
    // The output neither is a slice nor lies inside one (its files would join that slice's),
    // nor holds one (--force would replace it).
    const auto within = [](const fs::path& inner, const fs::path& outer) {
        const fs::path rel = inner.lexically_relative(outer);
        return !rel.empty() && *rel.begin() != "..";
    };
    for (const auto& d : a.dirs) {
        const fs::path slice_abs = fs::weakly_canonical(fs::absolute(d), ec);
        if (slice_abs == out_abs)
            throw InputError(a.out, "is one of the slices: merge into another folder");
        if (within(out_abs, slice_abs))
            throw InputError(
                a.out, "lies inside the slice " + d + ": merge into a folder outside every slice");
        if (within(slice_abs, out_abs))
            throw InputError(a.out,
                             "holds the slice " + d + ": merge into a folder outside every slice");
    }
    std::vector<SliceIn> slices;
    for (const auto& d : a.dirs) slices.push_back(read_slice(d));
    const SliceIn& first = slices[0];
    for (size_t i = 1; i < slices.size(); ++i) check_same_run(first, slices[i]);
    check_same_sources(slices);
    const ByIndex by_index = check_complete(slices);
    const Gathered g = gather_rows(by_index, first.shard["units_total"].get<size_t>());

    RunFolder folder(a.out, a.force);
    const fs::path tmp = folder.partial();
    create_new_file(tmp / "results.csv", merged_csv(g));
    const size_t copied = copy_files(by_index, tmp);
    nlohmann::json run =
        merged_record(first, by_index, g, command_line,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    run["files"] = file_records(tmp);  // written last, as run writes it
    create_new_file(tmp / "run.json", run.dump(2) + "\n");
    folder.commit();
    std::cout << "merged " << by_index.size() << " slices: " << g.rows << " rows (" << g.failed
              << " failed), " << copied << " other file(s) -> " << folder.final_dir().string()
              << "\n";
    std::cout << verify_results_folder(folder.final_dir().string(), false) << "\n";
    return g.failed ? 1 : 0;
}

}  // namespace pxh
