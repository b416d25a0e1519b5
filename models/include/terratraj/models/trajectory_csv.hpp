#pragma once
// Reading and writing the contract's trajectory CSV: a header line, then one row per sample,
// `t,x,y,z,heading,roll,pitch,v,omega,curvature`, and for the Segway RMP `platform_pitch` after
// them (the contract's Additions).

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/models/trajectory.hpp"

namespace terratraj::models {

/// Reads a trajectory CSV. Columns may come in any order; x and y are required, every other
/// contract column is optional (missing ones are NaN and has_column is false); columns of other
/// names are skipped and listed in ignored_columns. Throws InputError naming the file and line
/// for: a missing or unreadable file, no header, a header without x or y, a repeated column, a
/// row with the wrong number of fields, a field that is not a finite number (columns other than
/// t, x and y may hold "nan": value not known), no data rows, or t (when present) not strictly
/// increasing.
Trajectory readTrajectoryCsv(const std::filesystem::path& path);
/// The same from a stream; `source_name` names it in error messages.
Trajectory readTrajectoryCsv(std::istream& in, const std::string& source_name);

/// Writes every contract column, in order, NaN written as "nan". With `platform` (the Segway
/// RMP's pitch response), a `platform_pitch` column [rad] follows: see platformPitchColumn().
/// Throws InputError if the file cannot be written.
void writeTrajectoryCsv(const Trajectory& trajectory, const std::filesystem::path& path,
                        const SegwayPitchResponse* platform = nullptr);
/// The same to a stream.
void writeTrajectoryCsv(const Trajectory& trajectory, std::ostream& out,
                        const SegwayPitchResponse* platform = nullptr);

/// The Segway RMP's platform pitch at each sample [rad]: `platform`'s pitch at the acceleration
/// of the segment after the sample ((v_next - v) / (t_next - t); the last sample: the segment
/// before it; a single sample: 0) and the sample's terrain pitch (the slope), as the check
/// takes it (models::checkTrajectory judges each segment by the smaller of its two ends, so a
/// value here may exceed pitch_max by what the next sample's slope takes off). NaN where t, v
/// or pitch is not known.
std::vector<double> platformPitchColumn(const Trajectory& trajectory,
                                        const SegwayPitchResponse& platform);

}  // namespace terratraj::models
