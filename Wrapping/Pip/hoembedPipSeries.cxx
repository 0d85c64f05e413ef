// hoembed._hoembed.SeriesFiles: the binding of hoembed::SeriesFiles (IO/Series), the
// series' files as vtkTimeSeriesWriter handles them (staging folder, refusals, .pvd,
// atomic swap-in, cleanup). The pip wheel's write_series (hoembed/series.py) writes each
// frame with the user's pip VTK into the staged path start_frame returns. Errors are the
// class's sentences, raised as RuntimeError (series.py turns them into HOEmbedError).
#include "hoembedSeriesFiles.h"

#include <nanobind/nanobind.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <optional>
#include <stdexcept>
#include <string>

namespace nb = nanobind;

namespace
{
void Raise(const std::string& error)
{
  if (!error.empty())
    throw std::runtime_error(error);
}
} // namespace

void BindSeries(nb::module_& m)
{
  using hoembed::SeriesFiles;
  nb::class_<SeriesFiles>(m, "SeriesFiles")
    .def(nb::init<>())
    .def(
      "begin", [](SeriesFiles& s, const std::string& pvd) { Raise(s.Begin(pvd)); },
      nb::arg("pvd_path"))
    .def(
      "start_frame",
      [](SeriesFiles& s, double time, const std::string& extension, const std::string& dataType) {
        std::string staged;
        Raise(s.StartFrame(time, extension, dataType, staged));
        return staged;
      },
      nb::arg("time"), nb::arg("extension"), nb::arg("data_type"),
      "The staged path to write the next frame to (extension 'vtu' or 'vtp'; '' refuses "
      "the frame as of data_type).")
    .def(
      "finish_frame", [](SeriesFiles& s, bool written) { Raise(s.FinishFrame(written)); },
      nb::arg("written"))
    .def("end", [](SeriesFiles& s) { Raise(s.End()); })
    .def("abandon", &SeriesFiles::Abandon)
    .def_prop_ro("is_open", &SeriesFiles::IsOpen)
    .def_prop_ro("number_of_frames", &SeriesFiles::GetNumberOfFrames)
    .def("frame_file_name", &SeriesFiles::GetFrameFileName, nb::arg("index"))
    .def_static(
      "input_times",
      [](const std::optional<std::vector<double>>& requested,
        const std::optional<std::vector<double>>& advertised) {
        bool timed = false;
        std::vector<double> times = SeriesFiles::InputTimes(
          requested ? &*requested : nullptr, advertised ? &*advertised : nullptr, timed);
        return nb::make_tuple(times, timed);
      },
      nb::arg("requested").none(), nb::arg("advertised").none(),
      "(times, timed): the times a pipeline input is written at, and whether each update "
      "asks for its time.")
    .def_static("input_failed", &SeriesFiles::InputFailed, nb::arg("time"), nb::arg("step"))
    .def_static(
      "collection_text", &SeriesFiles::CollectionText, nb::arg("times"), nb::arg("relative_paths"));
}
