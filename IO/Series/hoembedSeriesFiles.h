/**
 * @file hoembedSeriesFiles.h
 * @brief The files of a time series (one step file per frame plus a .pvd collection),
 * VTK-free: where each frame goes, the .pvd text, and the atomic swap-in.
 *
 * What vtkTimeSeriesWriter does around writing each frame, so that any binding (the VTK
 * writer, or the pip wheel writing frames with the user's pip VTK from Python) runs the
 * same code. The binding writes each frame's data itself, into the staging path this
 * class gives it.
 *
 * Layout: for the collection `out/beam.pvd` the step files are
 * `out/beam/beam_NNNNNN.vtu` (or `.vtp`), referred to by relative path from the .pvd.
 *
 * No half-written series: Begin refuses up front (nothing written) a .pvd path that is a
 * folder, a step folder path that is a file and a step folder holding files that are not
 * step files of this series (the folder is replaced as a whole); then the frames go into
 * a staging folder beside the final one (`out/.beam.staging`), and End writes the .pvd
 * through `out/beam.pvd.part` and swaps both in: the old step folder moved aside, the
 * staging folder renamed in its place, the .pvd renamed over the old one (atomic), the
 * old folder removed. Any failure (and a series still open when the object is
 * destroyed) abandons the series: what it wrote is removed and an older series of the
 * same name stays exactly as it was.
 *
 * Usage: Begin(pvd); per frame StartFrame (gives the staged path), write the file,
 * FinishFrame(written); End(). Each returns an error sentence (empty: success); after an
 * error the series is abandoned. Not thread-safe (one series per object).
 */
#ifndef hoembedSeriesFiles_h
#define hoembedSeriesFiles_h

#include "hoembedIOSeriesModule.h"

#include <cstddef>
#include <string>
#include <vector>

namespace hoembed
{
class HOEMBEDIOSERIES_EXPORT SeriesFiles
{
public:
  SeriesFiles() = default;
  /// Abandons a series begun and never ended (its files are removed).
  ~SeriesFiles();
  SeriesFiles(const SeriesFiles&) = delete;
  SeriesFiles& operator=(const SeriesFiles&) = delete;

  /// Start a series written to `pvdPath` (abandons one still open): the refusals above,
  /// then creates the .pvd's folder if needed and an empty staging folder.
  std::string Begin(const std::string& pvdPath);

  /// Reserve the next frame at `time`. `extension`: "vtu" or "vtp"; empty when the
  /// binding has no writer for the data, whose type `dataType` names in the error.
  /// Refuses a series not open, a non-finite time, an unsupported type. On success
  /// `staged` is the path to write the frame to.
  std::string StartFrame(
    double time, const std::string& extension, const std::string& dataType, std::string& staged);
  /// Record the reserved frame (`written` true) or abandon the series (false: the
  /// binding could not write it; the error names the file).
  std::string FinishFrame(bool written);

  /// Write the .pvd and swap the series in. Refuses a series not open or without frames.
  std::string End();

  /// Remove what the open series wrote (staging folder, .pvd.part); nothing else.
  void Abandon();

  bool IsOpen() const
  {
    return this->Open;
  }
  /// Frames of the last (or current) series.
  std::size_t GetNumberOfFrames() const
  {
    return this->Files.size();
  }
  /// Final path of frame i ("" if out of range). While the series is open its files are
  /// still in the staging folder.
  const std::string& GetFrameFileName(std::size_t i) const;

  /// The times a pipeline input is written at (vtkTimeSeriesWriter::Write): `requested`
  /// when the caller gives times (TimeValues), else the input's TIME_STEPS when it
  /// advertises them, else one frame at 0. `timed`: whether each update asks for its
  /// time (UPDATE_TIME_STEP), false for an input without time.
  static std::vector<double> InputTimes(
    const std::vector<double>* requested, const std::vector<double>* advertised, bool& timed);
  /// The error when the input failed to update at step `step`, time `time`.
  static std::string InputFailed(double time, std::size_t step);

  /// The .pvd collection's text for frames at `times` in files `relativePaths`.
  static std::string CollectionText(
    const std::vector<double>& times, const std::vector<std::string>& relativePaths);
  /// `<stem>_NNNNNN.<extension>`
  static std::string FrameName(
    const std::string& stem, std::size_t index, const std::string& extension);
  /// True for a file this writer may replace in the step folder: `<stem>_NNNNNN.vtu/.vtp`
  /// (or with `.part`, left by writers before the staging folder).
  static bool IsStepFile(const std::string& name, const std::string& stem);

private:
  bool Open = false;
  std::string Pvd, Folder, Staging, Stem;
  std::vector<std::string> Files, Relative;
  std::vector<double> Times;
  // the frame between StartFrame and FinishFrame
  std::string PendingName, PendingStaged;
  double PendingTime = 0.0;
  bool Pending = false;
};
} // namespace hoembed

#endif
