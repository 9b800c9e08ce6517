// The report of bench_accuracy: one row per scene x setting, the closed forms, the CSV files,
// what to choose (derived from the rows, never typed by hand) and docs/accuracy.md.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "accuracy.h"

namespace ohrp::accuracy {

// One measured setting of a scene.
struct Row {
  std::string scene, sweep;
  Setting s;
  int iterations = 0;
  double tolerance = 0;
  std::string geometry;
  PieceResult r;
  std::string closed_form;
  double closed_form_error = std::nan("");
  bool reference = false;
};

// One closed-form check.
struct ClosedRow {
  std::string scene;
  Setting s;
  std::string quantity, unit;
  double value = std::nan(""), exact = std::nan(""), error = std::nan("");
  std::string note;
};

// "1.5e-05"-style text of v with a printf format; "" for NaN, "inf" for infinity.
std::string Num(double v, const char* fmt = "%.4g");
// "1/16 ms", "4 ms"
std::string DtName(double dt);
// "euler 1 ms soft iter 3 tol 1e-03 ico2" (the geometry only when not geometry_default)
std::string SettingName(const Setting& s, const std::string& geometry_default);

// accuracy.csv and closed_forms.csv; false when the file cannot be written.
bool WriteCsv(const std::string& path, const std::vector<Row>& rows);
bool WriteClosedCsv(const std::string& path, const std::vector<ClosedRow>& closed);

// What to choose for which need, per scene and contact model: printed on stdout, returned as a
// markdown table.
std::string ChoiceTable(const std::vector<SceneSpec>& scenes, const std::vector<Row>& rows);
// The observed order of the position error over the step sweep (markdown table).
std::string OrderTable(const std::vector<SceneSpec>& scenes, const std::vector<Row>& rows);

// Per scene with the soft soles, Euler from 1 ms up: the soft soles' errors and real-time
// factor beside the native contact's at the same step and their cost ratio (markdown; "" when
// no scene has soft rows).
std::string SoftStepTable(const std::vector<SceneSpec>& scenes, const std::vector<Row>& rows);

// The reference check rows (the reference's setting at half its step), markdown; "" when none.
std::string ReferenceCheckTable(const std::vector<Row>& rows);

// The headline: the fastest soft-sole setting of hrp1s_stand within 1 mm, its real-time factor
// over that of its reference (ref_rtf; NaN when the scene was not run).
struct Headline {
  double ratio = std::nan("");
  std::string text;                                            // empty when none
  std::string ratio_text = "(no hrp1s_stand scene in this run)";
};
Headline StandingHeadline(const std::vector<Row>& rows, double ref_rtf);

struct DocsInput {
  bool quick = false;
  int restarts = 0, piece_windows = 0;
  double cpu = 0;  // [s] of CPU the run took
  const std::vector<SceneSpec>* scenes = nullptr;
  const std::vector<std::string>* skipped = nullptr;
  const std::vector<Row>* rows = nullptr;
  const std::vector<ClosedRow>* closed = nullptr;
  std::string choices, orders, refcheck, headline, soft_steps;
};
// Writes docs/accuracy.md; false when it cannot be written.
bool WriteDocs(const std::string& path, const DocsInput& in);

}  // namespace ohrp::accuracy
