// hoembed::SeriesFiles alone (no VTK writer): the layout of a series, the .pvd read back
// with VTK's own XML parser (vtkXMLDataParser: its times are the doubles written, its
// files exist), the refusals before anything is written, and no half-written series: a
// frame the binding could not write, or an object destroyed mid-series, leaves an older
// series byte for byte as it was and nothing else. The frames here are small text files:
// the class never reads them.
#include "hoembedSeriesFiles.h"
#include "hoembedTestUtilities.h"

#include "vtkNew.h"
#include "vtkXMLDataElement.h"
#include "vtkXMLDataParser.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace
{
std::string ReadAll(const fs::path& path)
{
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// every file under `root` (relative path -> bytes)
std::map<std::string, std::string> Snapshot(const fs::path& root)
{
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(root))
  {
    if (e.is_regular_file())
      out[fs::relative(e.path(), root).string()] = ReadAll(e.path());
    else if (e.is_directory())
      out[fs::relative(e.path(), root).string() + "/"] = "";
  }
  return out;
}

// a series of `times.size()` frames named `ext`, each frame a text file; "" on success
std::string WriteSeries(
  const std::string& pvd, const std::vector<double>& times, const std::string& ext)
{
  hoembed::SeriesFiles files;
  std::string error = files.Begin(pvd);
  for (size_t k = 0; error.empty() && k < times.size(); ++k)
  {
    std::string staged;
    error = files.StartFrame(times[k], ext, "vtkPolyData", staged);
    if (error.empty())
    {
      std::ofstream(staged) << "frame " << k << " of " << pvd;
      error = files.FinishFrame(true);
    }
  }
  return error.empty() ? files.End() : error;
}

bool Contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}
} // namespace

int main(int, char*[])
{
  const fs::path dir = fs::current_path() / "series_files_test";
  fs::remove_all(dir);
  const std::string pvd = (dir / "out" / "beam.pvd").string();

  // A series: frames staged, then swapped in; the .pvd as VTK's parser reads it.
  const std::vector<double> times = { 0.0, 0.1, 1.0 / 3.0, 1e-300, -2.5 };
  {
    hoembed::SeriesFiles files;
    HOEMBED_CHECK(files.Begin(pvd).empty(), "Begin failed");
    HOEMBED_CHECK(fs::is_directory(dir / "out" / ".beam.staging"), "no staging folder");
    for (size_t k = 0; k < times.size(); ++k)
    {
      std::string staged;
      const std::string error = files.StartFrame(times[k], k % 2 ? "vtp" : "vtu", "", staged);
      HOEMBED_CHECK(error.empty(), "StartFrame %zu: %s", k, error.c_str());
      HOEMBED_CHECK(fs::path(staged).parent_path() == dir / "out" / ".beam.staging",
        "frame %zu staged at %s", k, staged.c_str());
      std::ofstream(staged) << "frame " << k;
      HOEMBED_CHECK(files.FinishFrame(true).empty(), "FinishFrame %zu failed", k);
      HOEMBED_CHECK(!fs::exists(pvd), "the .pvd exists before End");
    }
    HOEMBED_CHECK(files.End().empty(), "End failed");
    HOEMBED_CHECK(
      files.GetNumberOfFrames() == times.size(), "%zu frames", files.GetNumberOfFrames());
    HOEMBED_CHECK(files.GetFrameFileName(1) == (dir / "out" / "beam" / "beam_000001.vtp").string(),
      "frame 1 is %s", files.GetFrameFileName(1).c_str());
    HOEMBED_CHECK(files.GetFrameFileName(99).empty(), "frame 99 has a name");
  }
  {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir / "out"))
      names.push_back(e.path().filename().string());
    HOEMBED_CHECK(
      names.size() == 2, "%zu entries beside the series (staging or .part left?)", names.size());
    vtkNew<vtkXMLDataParser> parser;
    parser->SetFileName(pvd.c_str());
    HOEMBED_CHECK(parser->Parse() == 1, "VTK cannot parse the .pvd");
    vtkXMLDataElement* root = parser->GetRootElement();
    HOEMBED_CHECK(root && std::string(root->GetName()) == "VTKFile" &&
        std::string(root->GetAttribute("type")) == "Collection",
      "not a VTKFile Collection");
    vtkXMLDataElement* collection = root ? root->FindNestedElementWithName("Collection") : nullptr;
    HOEMBED_CHECK(collection && collection->GetNumberOfNestedElements() == int(times.size()),
      "the collection does not list %zu data sets", times.size());
    for (int k = 0; collection && k < collection->GetNumberOfNestedElements(); ++k)
    {
      vtkXMLDataElement* ds = collection->GetNestedElement(k);
      const double t = std::stod(ds->GetAttribute("timestep"));
      HOEMBED_CHECK(t == times[k], "data set %d: time %.17g read back as %.17g", k, times[k], t);
      const fs::path file = dir / "out" / ds->GetAttribute("file");
      HOEMBED_CHECK(fs::exists(file) && ReadAll(file) == "frame " + std::to_string(k),
        "data set %d: file %s missing or not frame %d", k, file.string().c_str(), k);
    }
  }

  // A frame the binding could not write, and an object destroyed mid-series: the old
  // series stays as it was, and nothing else is left.
  const auto before = Snapshot(dir);
  {
    hoembed::SeriesFiles files;
    HOEMBED_CHECK(files.Begin(pvd).empty(), "second Begin failed");
    std::string staged;
    files.StartFrame(7.0, "vtu", "", staged);
    std::ofstream(staged) << "new frame";
    files.FinishFrame(true);
    files.StartFrame(8.0, "vtu", "", staged);
    std::ofstream(staged) << "half a fr";
    const std::string error = files.FinishFrame(false);
    HOEMBED_CHECK(Contains(error, "Frame 1 (t = 8): cannot write '" + staged + "'"), "message: %s",
      error.c_str());
    HOEMBED_CHECK(!files.IsOpen(), "the series is still open after a failed frame");
    HOEMBED_CHECK(Snapshot(dir) == before, "a failed frame changed the old series");
    HOEMBED_CHECK(
      Contains(files.End(), "EndSeries called without BeginSeries()"), "End after failure");
  }
  {
    hoembed::SeriesFiles files;
    files.Begin(pvd);
    std::string staged;
    files.StartFrame(1.0, "vtp", "", staged);
    std::ofstream(staged) << "new frame";
    files.FinishFrame(true);
  } // destroyed before End
  HOEMBED_CHECK(Snapshot(dir) == before, "an object destroyed mid-series changed the old series");

  // A shorter re-run replaces the series whole (no stale frames).
  HOEMBED_CHECK(WriteSeries(pvd, { 5.0, 6.0 }, "vtp").empty(), "re-run failed");
  {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir / "out" / "beam"))
      n += e.path().filename().string().rfind("beam_00000", 0) == 0;
    HOEMBED_CHECK(n == 2, "%zu frames after a 2-frame re-run", n);
    HOEMBED_CHECK(!Contains(ReadAll(pvd), "beam_000002"), "the .pvd names an old frame");
  }

  // Refusals: nothing is written.
  fs::create_directories(dir / "refuse" / "d.pvd");
  std::string error = WriteSeries((dir / "refuse" / "d.pvd").string(), { 0.0 }, "vtu");
  HOEMBED_CHECK(Contains(error, "d.pvd': that path is a folder."), "message: %s", error.c_str());
  std::ofstream((dir / "refuse" / "f").string()) << "a file";
  error = WriteSeries((dir / "refuse" / "f.pvd").string(), { 0.0 }, "vtu");
  HOEMBED_CHECK(Contains(error, "its step folder '") && Contains(error, "' is a file."),
    "message: %s", error.c_str());
  fs::create_directories(dir / "refuse" / "mine");
  std::ofstream((dir / "refuse" / "mine" / "notes.txt").string()) << "keep me";
  std::ofstream((dir / "refuse" / "mine" / "mine_000000.vtu").string()) << "a step file";
  error = WriteSeries((dir / "refuse" / "mine.pvd").string(), { 0.0 }, "vtu");
  HOEMBED_CHECK(Contains(error, "holds 'notes.txt', which is not a step file of this series"),
    "message: %s", error.c_str());
  error = WriteSeries((dir / "refuse" / ".pvd").string(), { 0.0 }, "vtu");
  HOEMBED_CHECK(
    Contains(error, "has no file name (or starts with '.')"), "message: %s", error.c_str());
  error = WriteSeries("", { 0.0 }, "vtu");
  HOEMBED_CHECK(Contains(error, "is not set"), "message: %s", error.c_str());
  const auto refused = Snapshot(dir / "refuse");
  HOEMBED_CHECK(
    refused.size() == 5, "%zu entries after the refusals (something written)", refused.size());
  error = WriteSeries(
    (dir / "refuse" / "t.pvd").string(), { 0.0, std::numeric_limits<double>::quiet_NaN() }, "vtu");
  HOEMBED_CHECK(Contains(error, "Frame 1: the time is nan (a finite time is needed)."),
    "message: %s", error.c_str());
  error = WriteSeries((dir / "refuse" / "t.pvd").string(), { 0.0 }, "");
  HOEMBED_CHECK(Contains(error,
                  "Frame 0: unsupported data type vtkPolyData (vtkUnstructuredGrid "
                  "or vtkPolyData expected)."),
    "message: %s", error.c_str());
  error = WriteSeries((dir / "refuse" / "t.pvd").string(), {}, "vtu");
  HOEMBED_CHECK(
    Contains(error, "The series has no frames: nothing written."), "message: %s", error.c_str());
  HOEMBED_CHECK(Snapshot(dir / "refuse") == refused, "a refused frame left files");
  {
    hoembed::SeriesFiles files;
    std::string staged;
    error = files.StartFrame(0.0, "vtu", "", staged);
    HOEMBED_CHECK(Contains(error, "outside BeginSeries()") && staged.empty(),
      "a frame outside a series: %s", error.c_str());
  }

  // The step files it may replace, and no others.
  using hoembed::SeriesFiles;
  HOEMBED_CHECK(SeriesFiles::IsStepFile("s_000012.vtu", "s") &&
      SeriesFiles::IsStepFile("s_999999.vtp.part", "s"),
    "step files refused");
  HOEMBED_CHECK(!SeriesFiles::IsStepFile("s_00001.vtu", "s") &&
      !SeriesFiles::IsStepFile("s_000001.vti", "s") &&
      !SeriesFiles::IsStepFile("t_000001.vtu", "s") &&
      !SeriesFiles::IsStepFile("s_0000a1.vtu", "s") &&
      !SeriesFiles::IsStepFile("s_000001.vtu.bak", "s"),
    "a foreign file taken for a step file");
  HOEMBED_CHECK(SeriesFiles::FrameName("beam", 42, "vtu") == "beam_000042.vtu", "frame name");

  fs::remove_all(dir);
  return hoembed_test::Report("TestSeriesFiles");
}
