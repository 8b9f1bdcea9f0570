// The recording format (Documentation/recording-format.md): one CSV time series of an oedometer
// experiment or simulation (lab time axis) plus a JSON protocol file (device, geometry, material,
// steps). Used by the OedometerRelaxation driver (writer), by pdpm-recording-check (validator) and
// by anything comparing a simulation with lab data sample by sample.
#pragma once
#include <string>
#include <vector>

#include "IO/Json.h"

namespace pdpm::recording {

// ---- time series ---------------------------------------------------------------------------------

/// The channels with a defined meaning and unit. `time_s` is required, plus at least one measured
/// channel (every name here except time_s, step, dem_time_s, Ek_over_Ep, inertial_number).
struct ChannelInfo {
    const char* name;
    const char* meaning;
    bool measured;  ///< counts as a measured channel
};
const std::vector<ChannelInfo>& knownChannels();

struct Recording {
    std::vector<std::string> comments;  ///< comment lines without the leading "# "
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
    std::vector<long> rowLines;  ///< 1-based line in the file of each row (filled by checkRecording)

    int column(const std::string& name) const;  ///< -1 if absent
    std::vector<double> values(const std::string& name) const;  ///< InputError if absent
};

struct Problem {
    long line;  ///< 1-based line in the file (0: the file as a whole)
    std::string message;
};

/// Checks recording text; returns every problem found (empty: valid). When `out` is given and the
/// text is valid, the parsed recording is stored there.
std::vector<Problem> checkRecording(const std::string& text, Recording* out = nullptr);
/// Reads a recording; InputError "PATH:LINE: message" with the first problem.
Recording readRecording(const std::string& path);
/// Writes a recording atomically (17-digit numbers); InputError if it would not be valid.
void writeRecording(const std::string& path, const Recording& r);

// ---- protocol ------------------------------------------------------------------------------------

/// One protocol step. Velocities are piston speeds (m/s, > 0), stresses axial stresses (Pa).
struct Step {
    enum class Kind { Ramp, HoldPosition, Unload, HoldStress };
    Kind kind = Kind::Ramp;
    double velocity = 0;      ///< ramp / unload
    /// ramp: reach >= it (>= 0); unload: reach <= it, where a negative target is a tension (lift-off test:
    /// the unload goes on past zero force and ends at the target or when the piston has come free)
    double targetStress = 0;
    double duration = 0;      ///< holds, lab seconds
    double stress = -1;       ///< hold_stress: applied stress (Pa); < 0: the stress at the start of the hold
};
const char* stepTypeName(Step::Kind k);

struct Protocol {
    std::string source = "simulation";  ///< "simulation" or "experiment"
    std::string device = "periodic";    ///< "ft4", "lambdameter", "periodic", or another name
    double diameter = 0;                ///< m (0: laterally periodic)
    double height = 0;                  ///< m, fill height
    double wallFriction = 0;
    /// device.zero_before_contact: the load cell reads zero with the piston free, and the record
    /// begins with the piston just touching the bed or before (no stress before its first sample)
    bool zeroBeforeContact = false;
    Json material = Json::object();     ///< free-form material description
    Json extra = Json::object();        ///< free-form: time scaling, seeds, fitted values ...
    std::vector<Step> steps;
};

Json protocolToJson(const Protocol& p);
/// Strict: unknown step types, missing or out-of-range values raise InputError naming the key path
/// ("steps[2].velocity_m_s: ...").
Protocol protocolFromJson(const Json& j);
Protocol readProtocol(const std::string& path);
void writeProtocol(const std::string& path, const Protocol& p);

/// A hold of a simulation as the OedometerRelaxation driver lists it in the protocol file's
/// "extra": {"holds": [...]} (Documentation/recording-format.md, "Hold results of a simulation").
struct HoldSummary {
    bool position = true;                  ///< "hold_position" (false: "hold_stress", a creep step)
    int step = -1;                         ///< index of the protocol step
    double labStart = 0, stressStart = 0;  ///< lab time (s) and axial stress (Pa) when the hold's clock starts
    double fitC = -1, fitT0 = -1;          ///< Eq. 4.3 fit of the hold (-1: none or failed)
};
/// The holds of `protocol.extra.holds` (empty when there are none); InputError naming the entry when
/// one is malformed.
std::vector<HoldSummary> protocolHolds(const Protocol& protocol);

/// Steps from the command-line syntax, comma separated:
///   ramp:VELOCITY_m_s:TARGET_Pa   hold:DURATION_s   unload:VELOCITY_m_s:TARGET_Pa
///   creep:DURATION_s[:STRESS_Pa]
std::vector<Step> parseSteps(const std::string& text);
std::string formatSteps(const std::vector<Step>& steps);
/// Table 4.3 protocols 1-9: five ramps at the protocol's velocity to 5, 10, ..., 25 kPa (capped at
/// maxStress, e.g. 22 kPa for the FT4), each followed by a hold of the protocol's duration.
/// `stressScale` multiplies the targets (scaled-down tests). InputError for n outside 1..9.
std::vector<Step> presetSteps(int n, double maxStress = 25e3, double stressScale = 1.0);

// ---- analysis ------------------------------------------------------------------------------------

struct RelaxationFit {
    double C = 0, t0 = 0, rms = 0;  ///< rms: of f/f_max - model
    bool ok = false;
};
/// Least-squares fit of f/f_max = (1 + t/t0)^(-C) (Eq. 4.3) to a hold curve, t from the start of the
/// hold (first sample: t = 0, f = f_max). Searches log t0 in [t0Min, t0Max]; C is linear in
/// log(1 + t/t0) for given t0 and is fitted in log space.
RelaxationFit fitRelaxation(const std::vector<double>& t, const std::vector<double>& f, double t0Min = 1e-4,
                            double t0Max = 1e3);

} // namespace pdpm::recording
