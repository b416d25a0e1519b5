#pragma once
// Kinodynamic look-up tables (003_...): speed limits over bins of pitch (1-D) and of
// roll x curvature (2-D), in the contract's JSON form (../shared/spec/interface.md).
//
// v_max[i] (or v_max[i][j]) holds for the bin between edges i and i+1 (and j, j+1); a bin
// with no data holds 0; outside the edges the nearest bin holds. Two lookups:
//  - by bin (lookup()): the contract's rule, piecewise constant;
//  - smooth (smoothLookup()): C1 for optimisers. Bin values sit at the bin centres and are
//    joined by cubic Hermite pieces with finite-difference slopes (zero slope at the outermost
//    centres, constant beyond them); the 2-D table is the tensor product of the 1-D rule. It
//    passes through every bin value at the bin's centre, may overshoot slightly between
//    bins of very different values, and never returns less than 0.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace terratraj::models {

/// Bin edges, strictly increasing, at least two.
class BinEdges {
 public:
  BinEdges() = default;
  /// Throws InputError (naming `what`) unless there are >= 2 finite, strictly increasing edges.
  BinEdges(std::vector<double> edges, const std::string& what);

  const std::vector<double>& edges() const { return edges_; }
  int binCount() const { return static_cast<int>(edges_.size()) - 1; }
  /// The bin holding x; the nearest bin outside the edges (and for NaN, bin 0).
  int binOf(double x) const;
  /// Centre of bin i.
  double centre(int i) const { return 0.5 * (edges_[i] + edges_[i + 1]); }

 private:
  std::vector<double> edges_;
};

/// Pitch [rad] -> v_max [m/s] (pitch > 0 nose up, docs/conventions.md).
class PitchSpeedTable {
 public:
  PitchSpeedTable() = default;
  /// Throws InputError if v_max does not have one finite value >= 0 per bin.
  PitchSpeedTable(BinEdges pitch_edges, std::vector<double> v_max);

  const BinEdges& pitchEdges() const { return pitch_edges_; }
  const std::vector<double>& vMax() const { return v_max_; }
  /// v_max of the bin holding `pitch` [m/s].
  double lookup(double pitch) const;
  /// C1 version [m/s]; derivative by pitch into *d_pitch when not null.
  double smoothLookup(double pitch, double* d_pitch = nullptr) const;

 private:
  BinEdges pitch_edges_;
  std::vector<double> v_max_;
};

/// Roll [rad] x curvature [1/m] -> v_max [m/s]; v_max(i, j) for roll bin i, curvature bin j.
class RollCurvatureSpeedTable {
 public:
  RollCurvatureSpeedTable() = default;
  /// Throws InputError unless v_max is (roll bins) x (curvature bins) of finite values >= 0.
  RollCurvatureSpeedTable(BinEdges roll_edges, BinEdges curvature_edges, Eigen::MatrixXd v_max);

  const BinEdges& rollEdges() const { return roll_edges_; }
  const BinEdges& curvatureEdges() const { return curvature_edges_; }
  const Eigen::MatrixXd& vMax() const { return v_max_; }
  /// v_max of the bin holding (roll, curvature) [m/s].
  double lookup(double roll, double curvature) const;
  /// C1 version [m/s]; derivatives into *d_roll, *d_curvature when not null. No allocation.
  double smoothLookup(double roll, double curvature, double* d_roll = nullptr,
                      double* d_curvature = nullptr) const;

 private:
  BinEdges roll_edges_;
  BinEdges curvature_edges_;
  Eigen::MatrixXd v_max_;
};

/// Reads a pitch table (`"kind": "pitch"`). Throws InputError naming the file and key.
PitchSpeedTable readPitchTable(const std::filesystem::path& path);
/// Reads a roll x curvature table (`"kind": "roll_curvature"`). Throws InputError.
RollCurvatureSpeedTable readRollCurvatureTable(const std::filesystem::path& path);
/// The "kind" of a table file ("pitch" or "roll_curvature"). Throws InputError.
std::string readTableKind(const std::filesystem::path& path);

/// Writes a table as the contract's JSON. Throws InputError if the file cannot be written.
void writeTable(const PitchSpeedTable& table, const std::filesystem::path& path);
void writeTable(const RollCurvatureSpeedTable& table, const std::filesystem::path& path);
/// The contract's JSON text of a table (one object).
std::string tableJson(const PitchSpeedTable& table);
std::string tableJson(const RollCurvatureSpeedTable& table);

}  // namespace terratraj::models
