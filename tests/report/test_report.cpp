// report: the HTML page of one session's pipeline outputs, parsed back: well-formed, the merge,
// frame, tooltip and error tables hold the JSON inputs' numbers, the embedded images decode to the PNGs,
// every input text is escaped, the same inputs give the same bytes, and a folder missing an input is a
// clear error that leaves nothing behind.
#include <gtest/gtest.h>
#include <spdlog/fmt/fmt.h>

#include <cstring>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>

#include "support/run_tool.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/report/report.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

// --- A small HTML reader, enough for the page report writes ------------------------------------------

struct Token {
  bool is_tag = false, closing = false;
  std::string name;                               // tag name, lower case
  std::map<std::string, std::string> attributes;  // values unescaped
  std::string text;                               // text tokens, unescaped
};

std::string unescape(const std::string& text) {
  static const std::pair<const char*, const char*> entities[] = {
      {"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&#39;", "'"}, {"&amp;", "&"}};
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    bool replaced = false;
    if (text[i] == '&')
      for (const auto& [entity, character] : entities)
        if (text.compare(i, std::strlen(entity), entity) == 0) {
          out += character;
          i += std::strlen(entity);
          replaced = true;
          break;
        }
    if (replaced) continue;
    EXPECT_NE(text[i], '&') << "unknown entity at: " << text.substr(i, 12);
    out += text[i++];
  }
  return out;
}

std::vector<Token> tokenize(const std::string& html) {
  std::vector<Token> tokens;
  std::size_t i = 0;
  while (i < html.size()) {
    if (html[i] != '<') {
      const std::size_t end = std::min(html.find('<', i), html.size());
      Token text;
      const std::string raw = html.substr(i, end - i);
      EXPECT_EQ(raw.find('>'), std::string::npos) << "unescaped > in text: " << raw;
      text.text = unescape(raw);
      tokens.push_back(text);
      i = end;
      continue;
    }
    if (html.compare(i, 9, "<!DOCTYPE") == 0) {
      i = html.find('>', i) + 1;
      continue;
    }
    Token tag;
    tag.is_tag = true;
    std::size_t j = i + 1;
    if (html[j] == '/') tag.closing = true, ++j;
    while (j < html.size() && std::isalnum(static_cast<unsigned char>(html[j]))) tag.name += html[j++];
    while (j < html.size() && html[j] != '>') {
      if (std::isspace(static_cast<unsigned char>(html[j]))) {
        ++j;
        continue;
      }
      std::string key;
      while (j < html.size() && html[j] != '=' && html[j] != '>' && !std::isspace(static_cast<unsigned char>(html[j])))
        key += html[j++];
      std::string value;
      if (html[j] == '=') {
        EXPECT_EQ(html[j + 1], '"') << "unquoted attribute " << key;
        const std::size_t close = html.find('"', j + 2);
        value = unescape(html.substr(j + 2, close - j - 2));
        j = close + 1;
      }
      tag.attributes[key] = value;
    }
    tokens.push_back(tag);
    i = j + 1;
  }
  return tokens;
}

// Every element closed, in order (void elements excepted).
void expect_well_formed(const std::vector<Token>& tokens) {
  std::vector<std::string> open;
  for (const auto& t : tokens) {
    if (!t.is_tag || t.name == "meta" || t.name == "img" || t.name == "br") continue;
    if (!t.closing) {
      open.push_back(t.name);
      continue;
    }
    ASSERT_FALSE(open.empty()) << "</" << t.name << "> closes nothing";
    ASSERT_EQ(open.back(), t.name);
    open.pop_back();
  }
  EXPECT_TRUE(open.empty());
}

// The body rows of the table with this id: each row's cells' text.
std::vector<std::vector<std::string>> table_rows(const std::vector<Token>& tokens, const std::string& id) {
  std::vector<std::vector<std::string>> rows;
  bool in_table = false, in_head = false, in_cell = false;
  for (const auto& t : tokens) {
    if (!in_table) {
      in_table = t.is_tag && !t.closing && t.name == "table" && t.attributes.count("id") && t.attributes.at("id") == id;
      continue;
    }
    if (t.is_tag && t.name == "table") break;
    if (t.is_tag && t.name == "thead") in_head = !t.closing;
    if (in_head) continue;
    if (t.is_tag && !t.closing && t.name == "tr") rows.emplace_back();
    if (t.is_tag && (t.name == "td" || t.name == "th")) {
      in_cell = !t.closing;
      if (in_cell) rows.back().emplace_back();
    }
    if (!t.is_tag && in_cell) rows.back().back() += t.text;
  }
  return rows;
}

std::map<std::string, std::string> images(const std::vector<Token>& tokens) {
  std::map<std::string, std::string> out;
  for (const auto& t : tokens)
    if (t.is_tag && t.name == "img") out[t.attributes.at("id")] = t.attributes.at("src");
  return out;
}

std::string base64_decode(const std::string& text) {
  static const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::uint32_t buffer = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    const auto value = alphabet.find(c);
    if (value == std::string::npos) {
      ADD_FAILURE() << "not base64: " << c;
      return {};
    }
    buffer = buffer << 6 | static_cast<std::uint32_t>(value);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((buffer >> bits) & 0xff);
    }
  }
  return out;
}

// --- One simulated session through the pipeline, once for all tests ------------------------------------

class Report : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = scratch_dir("report");
    const std::string s = (dir_ / "session").string(), o = (dir_ / "hoe").string();
    fs::create_directories(o);
    const std::vector<std::pair<std::string, std::string>> steps = {
        {"simulate-session", "--family hoe --seed 3 -o " + s},
        {"crop-cloud", s + " --all -o " + o + "/views"},
        {"merge-views", o + "/views/view_000.ply " + o + "/views/view_001.ply " + o + "/views/view_002.ply " + o +
                            "/views/view_003.ply " + o + "/views/view_004.ply -o " + o + "/model.ply --report " + o +
                            "/merge_report.json"},
        {"estimate-frame", o + "/model.ply -o " + o + "/frame.json"},
        {"find-tooltip", o + "/model.ply --frame " + o + "/frame.json -o " + o + "/tooltip.json"},
        {"evaluate", "--truth " + s + "/ground_truth.json --frame " + o + "/frame.json --tooltip " + o +
                         "/tooltip.json -o " + o + "/evaluation.json"},
        {"render",
         o + "/model.ply --frame " + o + "/frame.json --tooltip " + o + "/tooltip.json -o " + o + "/model.png"},
        {"render", "--session " + s + " -o " + o + "/sheet.png"},
        {"report", o + " -o " + o + "/report.html"},
    };
    for (const auto& [tool, args] : steps) {
      const auto run = run_tool(tool, "-q " + args);
      ASSERT_EQ(run.exit_code, 0) << tool << " " << args << "\n" << run.err;
    }
  }
  static fs::path outputs() { return dir_ / "hoe"; }
  static Json json(const std::string& file) { return read_json((outputs() / file).string()); }
  // A copy of the outputs in `name` next to them, to spoil.
  static fs::path copy_outputs(const std::string& name) {
    const fs::path copy = dir_ / name;
    fs::remove_all(copy);
    fs::create_directories(copy);
    for (const char* f :
         {"merge_report.json", "frame.json", "tooltip.json", "evaluation.json", "model.png", "sheet.png"})
      fs::copy_file(outputs() / f, copy / f);
    return copy;
  }
  static inline fs::path dir_;
};

}  // namespace

TEST(ReportText, EscapeAndBase64) {
  EXPECT_EQ(html_escape("a<b>&\"c'd"), "a&lt;b&gt;&amp;&quot;c&#39;d");
  const std::pair<const char*, const char*> vectors[] = {{"", ""},
                                                         {"f", "Zg=="},
                                                         {"fo", "Zm8="},
                                                         {"foo", "Zm9v"},
                                                         {"foob", "Zm9vYg=="},
                                                         {"fooba", "Zm9vYmE="},
                                                         {"foobar", "Zm9vYmFy"}};  // RFC 4648 section 10
  for (const auto& [plain, encoded] : vectors) EXPECT_EQ(base64_encode(plain), encoded);
  const std::string binary("\x00\xff\x10\x80", 4);
  EXPECT_EQ(base64_decode(base64_encode(binary)), binary);
}

TEST_F(Report, TablesHoldTheJsonNumbers) {
  const std::string html = slurp(outputs() / "report.html");
  const auto tokens = tokenize(html);
  expect_well_formed(tokens);

  const Json merge = json("merge_report.json");
  const auto rows = table_rows(tokens, "merge");
  ASSERT_EQ(rows.size(), merge["views"].size());
  int accepted = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Json& v = merge["views"][i];
    const auto& r = rows[i];
    SCOPED_TRACE("view " + std::to_string(i));
    ASSERT_EQ(r.size(), 12u);
    EXPECT_EQ(number(r[0]), static_cast<double>(i));
    EXPECT_EQ(r[1], fs::path(v["file"].get<std::string>()).filename().string());
    EXPECT_EQ(r[2], v["accepted"].get<bool>() ? "accepted" : "rejected");
    accepted += v["accepted"].get<bool>();
    EXPECT_EQ(number(r[3]), v["points"].get<int>());
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(number(r[4 + a]), 1000 * v["correction"]["translation_m"][a].get<double>(), 0.051);
    EXPECT_NEAR(number(r[7]), v["correction"]["rotation_deg"].get<double>(), 0.0051);
    EXPECT_NEAR(number(r[8]), 100 * v["inlier_ratio"].get<double>(), 0.051);
    EXPECT_NEAR(number(r[9]), 1000 * v["inlier_rmse_m"].get<double>(), 0.0051);
    EXPECT_EQ(number(r[10]), v["smear_dropped"].get<int>());
    EXPECT_EQ(r[11], v["reason"].get<std::string>());
  }
  EXPECT_GE(accepted, 3);

  const Json frame = json("frame.json");
  const auto frame_rows = table_rows(tokens, "frame");
  ASSERT_EQ(frame_rows.size(), 4u);
  const char* keys[] = {"origin", "effector_axis", "handle_axis", "symmetry_axis"};
  for (int k = 0; k < 4; ++k)
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(number(frame_rows[k][1 + a]), frame[keys[k]][a].get<double>(), 5.1e-5) << keys[k];

  const Json tooltip = json("tooltip.json");
  const auto tip_rows = table_rows(tokens, "tooltip");
  ASSERT_EQ(tip_rows.size(), 2u);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(number(tip_rows[0][1 + a]), tooltip["position"][a].get<double>(), 5.1e-5);
    EXPECT_NEAR(number(tip_rows[1][1 + a]), tooltip["position_in_tool_frame"][a].get<double>(), 5.1e-5);
  }

  const Json evaluation = json("evaluation.json");
  const auto errors = table_rows(tokens, "errors");
  ASSERT_EQ(errors.size(), 5u);
  EXPECT_EQ(errors[0][0], "tooltip (mm)");
  EXPECT_NEAR(number(errors[0][1]), 1000 * evaluation["tooltip"]["error_m"].get<double>(), 0.051);
  EXPECT_NEAR(number(errors[1][1]), evaluation["frame"]["handle_axis_error_deg"].get<double>(), 0.0051);
  EXPECT_NEAR(number(errors[2][1]), evaluation["frame"]["effector_axis_error_deg"].get<double>(), 0.0051);
  EXPECT_NEAR(number(errors[3][1]), 1000 * evaluation["frame"]["origin_error_m"].get<double>(), 0.051);
  EXPECT_EQ(errors[4][1], evaluation["frame"]["right_handed"].get<bool>() ? "yes" : "no");
}

TEST_F(Report, ASearchedFrameShowsItsChoiceTheNextTipAndWhyItIsDoubtful) {
  // The session's frame, by the search (the default): its chosen hypothesis and the next whose tip lies
  // elsewhere.
  const std::string html = slurp(outputs() / "report.html");
  const auto tokens = tokenize(html);
  const Json searched = json("frame.json");
  const Json& hypotheses = searched["diagnostics"]["hypotheses"];
  const auto rows = table_rows(tokens, "hypotheses");
  ASSERT_GE(rows.size(), 1u);
  ASSERT_LE(rows.size(), 2u);
  EXPECT_EQ(rows[0][0], "chosen");
  EXPECT_EQ(rows[0][1], hypotheses[0]["handle"].get<std::string>());
  EXPECT_NEAR(number(rows[0][3]), hypotheses[0]["probability"].get<double>(), 0.0051);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(number(rows[0][4 + a]), hypotheses[0]["tooltip"][a].get<double>(), 5.1e-5);
  EXPECT_NE(html.find(fmt::format("the chosen tooltip's probability {:.2f}",
                                  searched["diagnostics"]["tooltip_probability"].get<double>())),
            std::string::npos);
  if (!searched["confidence"]["confident"].get<bool>()) EXPECT_NE(html.find("Doubtful: "), std::string::npos);

  // The same model's frame by the rules: a confidence note, no hypotheses.
  const fs::path copy = copy_outputs("rules");
  const auto frame = run_tool("estimate-frame", "-q " + (outputs() / "model.ply").string() + " --method rules -o " +
                                                    (copy / "frame.json").string());
  ASSERT_EQ(frame.exit_code, 0) << frame.err;
  const auto report = run_tool("report", "-q " + copy.string() + " -o " + (copy / "report.html").string());
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const std::string rules_html = slurp(copy / "report.html");
  const auto rules_tokens = tokenize(rules_html);
  expect_well_formed(rules_tokens);
  EXPECT_TRUE(table_rows(rules_tokens, "hypotheses").empty());
  const bool rules_confident = read_json((copy / "frame.json").string())["confidence"]["confident"].get<bool>();
  EXPECT_NE(rules_html.find(rules_confident ? "Confident." : "Doubtful: "), std::string::npos);
}

TEST_F(Report, ImagesAreEmbeddedAndDecode) {
  const std::string html = slurp(outputs() / "report.html");
  const auto found = images(tokenize(html));
  ASSERT_EQ(found.size(), 2u);
  for (const auto& [id, file] : std::map<std::string, std::string>{{"model", "model.png"}, {"sheet", "sheet.png"}}) {
    SCOPED_TRACE(id);
    ASSERT_TRUE(found.count(id));
    const std::string prefix = "data:image/png;base64,";
    ASSERT_EQ(found.at(id).compare(0, prefix.size(), prefix), 0);
    const std::string bytes = base64_decode(found.at(id).substr(prefix.size()));
    EXPECT_EQ(bytes, slurp(outputs() / file));
    const cv::Mat image = cv::imdecode(std::vector<unsigned char>(bytes.begin(), bytes.end()), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty());
    EXPECT_GT(image.cols, 500);
  }
  // Self-contained: nothing fetched, nothing run.
  for (const char* outside : {"http:", "https:", "<script", "<link", "file:"})
    EXPECT_EQ(html.find(outside), std::string::npos) << outside;
}

TEST_F(Report, SameInputsSameBytes) {
  const auto run = run_tool("report", "-q " + outputs().string() + " -o " + (dir_ / "again.html").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(slurp(dir_ / "again.html"), slurp(outputs() / "report.html"));
}

TEST_F(Report, EveryInputTextIsEscaped) {
  const fs::path copy = copy_outputs("a<b>&\"c");  // all but ' (the test's shell quotes with it)
  Json merge = json("merge_report.json");
  const std::string nasty = "<script>alert('x')</script> & \"q\" </td>";
  merge["views"][1]["reason"] = nasty;
  merge["views"][1]["file"] = "/x/<img src=x onerror=1>.ply";
  write_json((copy / "merge_report.json").string(), merge);
  const fs::path html_file = dir_ / "escaped.html";
  const auto run = run_tool("report", "-q '" + copy.string() + "' -o " + html_file.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string html = slurp(html_file);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<img src=x"), std::string::npos);
  const auto tokens = tokenize(html);
  expect_well_formed(tokens);
  const auto rows = table_rows(tokens, "merge");
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows[1][11], nasty);
  EXPECT_EQ(rows[1][1], "<img src=x onerror=1>.ply");
  std::string title;
  for (std::size_t i = 0; i + 1 < tokens.size(); ++i)
    if (tokens[i].is_tag && !tokens[i].closing && tokens[i].name == "h1") title = tokens[i + 1].text;
  EXPECT_EQ(title, "Session a<b>&\"c");
}

TEST_F(Report, WithoutGroundTruthNoErrorTable) {
  const fs::path copy = copy_outputs("recorded");
  fs::remove(copy / "evaluation.json");
  const auto run = run_tool("report", "-q " + copy.string() + " -o " + (copy / "report.html").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string html = slurp(copy / "report.html");
  EXPECT_TRUE(table_rows(tokenize(html), "errors").empty());
  EXPECT_NE(html.find("No ground truth"), std::string::npos);
}

TEST_F(Report, MissingOrBadInputIsAClearError) {
  for (const char* missing : {"merge_report.json", "frame.json", "tooltip.json", "model.png", "sheet.png"}) {
    SCOPED_TRACE(missing);
    const fs::path copy = copy_outputs("missing");
    fs::remove(copy / missing);
    const fs::path out = copy / "report.html";
    const auto run = run_tool("report", copy.string() + " -o " + out.string());
    EXPECT_EQ(run.exit_code, 2);
    expect_failure_left_nothing(run, missing, out, copy);
  }
  const fs::path copy = copy_outputs("bad");
  std::ofstream(copy / "sheet.png") << "not an image";
  write_json((copy / "frame.json").string(), json("tooltip.json"));  // a tooltip where the frame belongs
  for (const char* bad : {"frame.json", "sheet.png"}) {
    SCOPED_TRACE(bad);
    const fs::path out = copy / "report.html";
    const auto run = run_tool("report", copy.string() + " -o " + out.string());
    EXPECT_EQ(run.exit_code, 2);
    expect_failure_left_nothing(run, bad, out, copy);
    fs::copy_file(outputs() / bad, copy / bad, fs::copy_options::overwrite_existing);
  }
  const auto run = run_tool("report", (dir_ / "nowhere").string() + " -o " + (dir_ / "nowhere.html").string());
  EXPECT_EQ(run.exit_code, 2);
  expect_failure_left_nothing(run, "nowhere", dir_ / "nowhere.html", dir_);
}
