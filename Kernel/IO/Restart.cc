// Restart files: DPMBase::writeRestart / readRestart. Format in Documentation/restart.md.
// Text, numbers in shortest round-trip form (bitwise-exact), closed by a checksum line so that
// truncated or edited files are refused.
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "Core/DPMBase.h"
#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/NumberFormat.h"
#include "IO/RestartSeal.h"

namespace pdpm {

namespace {
constexpr const char* kMagic = "PowderDPM-restart";
constexpr int kVersion = 5;  // 3: walls carry their last force and torque; 4: relaxMemory; 5: viscTime, viscStiffnessRatio, viscTimeScale
constexpr int kOldestVersion = 4;  // version 4 files read with the viscous fields at their defaults (off)

void expect(std::istream& is, const std::string& tag, const std::string& file) {
    std::string t;
    is >> t;
    if (!is || t != tag) inputError("restart file " + file + ": expected '" + tag + "' but found '" + t + "'");
}

uint64_t fnv1a(const std::string& s) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) {
        h ^= c;
        h *= 1099511628211ull;
    }
    return h;
}
} // namespace

std::string restartChecksumLine(const std::string& body) {
    char tail[64];
    std::snprintf(tail, sizeof tail, "end %016" PRIx64 "\n", fnv1a(body));
    return tail;
}

std::string resealRestartText(const std::string& text) {
    const std::size_t endPos = text.rfind("\nend ");
    if (endPos == std::string::npos) return {};
    const std::string body = text.substr(0, endPos + 1);
    return body + restartChecksumLine(body);
}

namespace {
/// [from, to) of the value of the first line "KEY VALUE" of a restart text; false if there is none.
bool restartValueSpan(const std::string& text, const std::string& key, std::size_t& from, std::size_t& to) {
    const std::size_t at = text.find("\n" + key + " ");
    if (at == std::string::npos) return false;
    from = at + 2 + key.size();
    to = text.find('\n', from);
    return to != std::string::npos;
}
} // namespace

std::string restartValue(const std::string& text, const std::string& key) {
    std::size_t from = 0, to = 0;
    return restartValueSpan(text, key, from, to) ? text.substr(from, to - from) : std::string();
}

std::string withRestartValue(const std::string& text, const std::string& key, const std::string& value) {
    std::size_t from = 0, to = 0;
    if (!restartValueSpan(text, key, from, to)) return {};
    return resealRestartText(text.substr(0, from) + value + text.substr(to));
}

void DPMBase::writeRestart(const std::string& path) const {
    std::ostringstream os;
    os << kMagic << ' ' << kVersion << '\n';
    os << "program " << name_ << '\n';
    os << "law " << law_->name() << ' ' << law_->canonicalHistorySize() << '\n';
    os << "time " << fmt(time_) << " step " << step_ << " dt " << fmt(dt_) << '\n';
    os << "output " << outputIndex_ << ' ' << fmt(nextOutput_) << ' ' << fmt(outputEvery_) << '\n';
    os << "rng " << rng_ << '\n';
    os << "gravity " << fmt(gravity_) << " damping " << fmt(gammaBt_) << ' ' << fmt(gammaBr_) << '\n';
    box_.write(os);
    const auto pv = params_.values();
    os << "parameters " << pv.size() << '\n';
    for (const auto& [k, v] : pv) os << k << ' ' << (v.empty() ? "\"\"" : v) << '\n';
    os << "species " << species_.size() << '\n';
    for (int a = 0; a < species_.size(); ++a) os << species_[a].name << ' ' << fmt(species_[a].density) << '\n';
    for (int a = 0; a < species_.size(); ++a)
        for (int b = a; b < species_.size(); ++b) {
            os << a << ' ' << b << ' ';
            writeContactParameters(os, species_.pair(a, b));
            os << '\n';
        }
    os << "walls " << walls_.size() << '\n';
    for (const auto& w : walls_) {
        w->write(os);
        os << '\n';
    }
    const ParticleData& P = particles_;
    os << "particles " << P.size() << '\n';
    for (std::size_t i = 0; i < P.size(); ++i)
        os << fmt(P.x[i]) << ' ' << fmt(P.v[i]) << ' ' << fmt(P.w[i]) << ' ' << fmt(P.f[i]) << ' ' << fmt(P.t[i]) << ' '
           << fmt(P.r[i]) << ' ' << P.species[i] << ' ' << int(P.fixed[i]) << '\n';
    neighbours_.write(os, law_->omittedSlot());  // the canonical layout, whatever form ran
    std::vector<std::pair<std::string, std::string>> kv;
    saveDriverState(kv);
    os << "driver " << kv.size() << '\n';
    for (const auto& [k, v] : kv) os << k << ' ' << v << '\n';
    std::string body = os.str();
    body += restartChecksumLine(body);
    writeWholeFile(path, body);
}

void DPMBase::readRestart(const std::string& path, bool stateOnly) {
    const std::string text = readWholeFile(path);
    // Checksum line: the last line "end HEX".
    const std::size_t endPos = text.rfind("\nend ");
    if (text.rfind(kMagic, 0) != 0) inputError("restart file " + path + ": not a PowderDPM restart file (bad header)");
    if (endPos == std::string::npos) inputError("restart file " + path + ": truncated (no end line)");
    const std::string body = text.substr(0, endPos + 1);
    // The end line is exactly what the writer wrote (a missing final newline aside): nothing may
    // follow the checksum, on its line or after it.
    const std::string tail = text.substr(endPos + 1), want = restartChecksumLine(body);
    if (tail != want && tail + "\n" != want) {
        uint64_t stored = 0;
        if (tail.compare(0, want.size() - 1, want, 0, want.size() - 1) == 0)
            inputError("restart file " + path + ": text after the checksum (file appended to or corrupt)");
        if (std::sscanf(tail.c_str() + 4, "%" SCNx64, &stored) == 1 && stored == fnv1a(body))
            inputError("restart file " + path + ": malformed end line (expected 'end' and 16 lower-case hex digits)");
        inputError("restart file " + path + ": checksum mismatch (file corrupt or edited)");
    }

    std::istringstream is(body);
    std::string magic;
    int version = 0;
    is >> magic >> version;
    if (version < kOldestVersion || version > kVersion)
        inputError("restart file " + path + ": version " + std::to_string(version) + " not supported (expected " +
                   std::to_string(kOldestVersion) + " to " + std::to_string(kVersion) + ")");
    std::string prog, lawName;
    int hsize = 0;
    expect(is, "program", path);
    is >> prog;
    if (prog != name_ && !stateOnly)
        inputError("restart file " + path + " was written by " + prog + ", not by " + name_);
    expect(is, "law", path);
    is >> lawName >> hsize;
    // Resuming needs the file's law. A new experiment from the file's state (stateOnly) may name
    // another one with --contact_law: it is kept, and the file's contact histories and stored forces,
    // which belong to the file's law, are discarded (DPMBase::discardLoadedContacts, the one rule).
    const bool ownLaw = params_.wasSetOnCommandLine("contact_law") && lawName_ != lawName;
    if (ownLaw && !stateOnly)
        inputError("restart file " + path + " uses contact law '" + lawName + "' but --contact_law is '" + lawName_ + "'");
    auto law = makeContactLaw(lawName);
    if (law->historySize() != hsize)
        inputError("restart file " + path + ": law '" + lawName + "' history size mismatch");
    // values that pass the checksum but cannot be a run's state (an edited file) are refused here
    const auto invalid = [&](const std::string& what) { inputError("restart file " + path + ": invalid " + what); };
    expect(is, "time", path);
    time_ = readDouble(is);
    if (!is || !std::isfinite(time_) || time_ < 0) invalid("time");
    expect(is, "step", path);
    is >> step_;
    if (!is || step_ < 0) invalid("step");
    expect(is, "dt", path);
    const double dtFile = readDouble(is);
    if (!is || !std::isfinite(dtFile) || !(dtFile > 0)) invalid("dt");
    expect(is, "output", path);
    int outIndex = 0;
    is >> outIndex;
    const double nextOut = readDouble(is), outEvery = readDouble(is);
    // the next output lies ahead of the restart time (a file written by a run always has it there);
    // an interval too small to move it on is a run's own choice (--save_every far below the step):
    // the schedule then outputs every step (DPMBase::advanceNextOutput)
    if (!is || outIndex < 0 || !std::isfinite(nextOut) || !(nextOut > time_ - outEvery - dtFile) || !(outEvery >= 0) ||
        !std::isfinite(outEvery))
        invalid("output record");
    if (!stateOnly) {
        outputIndex_ = outIndex;
        nextOutput_ = nextOut;
        outputEvery_ = outEvery;
    }
    expect(is, "rng", path);
    is >> rng_;
    expect(is, "gravity", path);
    gravity_ = readVec3(is);
    expect(is, "damping", path);
    gammaBt_ = readDouble(is);
    gammaBr_ = readDouble(is);
    if (!is || !isFinite(gravity_) || !std::isfinite(gammaBt_) || !std::isfinite(gammaBr_) || gammaBt_ < 0 || gammaBr_ < 0)
        invalid("gravity or damping");
    box_.read(is);
    std::size_t np = 0;
    expect(is, "parameters", path);
    is >> np;
    for (std::size_t k = 0; k < np && is; ++k) {
        std::string name, value;
        is >> name;
        std::getline(is >> std::ws, value);
        if (value == "\"\"") value.clear();
        if (!stateOnly && params_.has(name) && !params_.wasSetOnCommandLine(name)) params_.set(name, value);
    }
    if (!stateOnly && !params_.wasSetOnCommandLine("dt")) dt_ = dtFile;
    if (!ownLaw) {
        law_ = std::move(law);
        lawName_ = lawName;
    }
    int ns = 0;
    expect(is, "species", path);
    is >> ns;
    if (!is || ns < 0 || ns > 10000) inputError("restart file " + path + ": malformed species section");
    species_.clear();
    std::vector<std::pair<std::string, double>> sp(ns);
    for (auto& [n, d] : sp) {
        is >> n;
        d = readDouble(is);
    }
    for (auto& [n, d] : sp) species_.add(n, d, ContactParameters{});
    for (int a = 0; a < ns; ++a)
        for (int b = a; b < ns; ++b) {
            int ia = -1, ib = -1;
            is >> ia >> ib;
            if (ia != a || ib != b) inputError("restart file " + path + ": malformed species pair table");
            ContactParameters p = readContactParameters(is, version);
            if (p.defined) species_.setPair(a, b, p);
            else species_.pairMutable(a, b) = species_.pairMutable(b, a) = p;
        }
    std::size_t nw = 0;
    expect(is, "walls", path);
    is >> nw;
    if (!is || nw > 100000) inputError("restart file " + path + ": malformed walls section");
    walls_.clear();
    for (std::size_t k = 0; k < nw; ++k) {
        walls_.push_back(Wall::read(is));
        if (walls_.back()->species < 0 || walls_.back()->species >= ns)
            inputError("restart file " + path + ": wall " + std::to_string(k) + " has an undefined species");
    }
    std::size_t n = 0;
    expect(is, "particles", path);
    is >> n;
    if (!is || n > (std::size_t(1) << 32)) inputError("restart file " + path + ": malformed particle count");
    particles_.clear();
    particles_.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 x = readVec3(is), v = readVec3(is), w = readVec3(is), f = readVec3(is), t = readVec3(is);
        const double r = readDouble(is);
        int s = 0, fixed = 0;
        is >> s >> fixed;
        if (!is || s < 0 || s >= ns || (fixed != 0 && fixed != 1) || !(r > 0) || !std::isfinite(r) || !isFinite(x) ||
            !isFinite(v) || !isFinite(w) || !std::isfinite(norm2(v) + norm2(w)) ||  // squares: the energies
            !isFinite(f) || !isFinite(t))
            inputError("restart file " + path + ": malformed particle record " + std::to_string(i));
        const std::size_t k = particles_.add(x, r, species_[s].density, s, v, w, fixed != 0);
        particles_.f[k] = f;
        particles_.t[k] = t;
    }
    neighbours_.read(is, n, nw, hsize);
    std::size_t nkv = 0;
    expect(is, "driver", path);
    is >> nkv;
    if (!is || nkv > body.size()) inputError("restart file " + path + ": malformed driver section");  // a line per key
    std::vector<std::pair<std::string, std::string>> kv(nkv);
    for (auto& [k, v] : kv) {
        is >> k;
        std::getline(is >> std::ws, v);
    }
    if (!is) inputError("restart file " + path + ": truncated driver section");
    if (stateOnly) {  // a new experiment: its clock starts at zero
        time_ = 0;
        step_ = 0;
        stateLoaded_ = true;
        if (ownLaw) discardLoadedContacts();  // ownLaw implies stateOnly (refused above otherwise)
        return;
    }
    loadDriverState(kv);
    // Energies written so far: keep the rows of RUN.ene up to the restart time.
    eneBuffer_.clear();
    if (std::filesystem::exists(outputPath(".ene"))) {
        std::istringstream ene(readWholeFile(outputPath(".ene")));
        std::string line;
        while (std::getline(ene, line)) {
            if (!line.empty() && line[0] != '#') {
                double t = 0;
                std::istringstream ls(line);
                t = readDouble(ls);
                if (!ls || t > time_ + 0.5 * dt_) break;
            }
            eneBuffer_ += line + '\n';
        }
    }
}

} // namespace pdpm
