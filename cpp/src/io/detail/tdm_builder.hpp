#pragma once
// Private: the TDM model builder that the KVN and the XML readers feed, so that both apply the same
// rules (CCSDS 503.0-B-2 sections 3.2-3.5) and name the same keyword in their errors.
#include <map>
#include <string>

#include "satgnc/io/tdm.hpp"

namespace satgnc::io::detail {

class TdmBuilder {
 public:
  explicit TdmBuilder(std::string source) : source_(std::move(source)) {}
  void version(const std::string& value, int line);
  void header(const std::string& key, const std::string& value, int line);
  void header_comment(const std::string& text) { tdm_.header.comments.push_back(text); }
  void begin_segment(int line);
  void meta(const std::string& key, const std::string& value, int line);
  void meta_comment(const std::string& text) { tdm_.segments.back().metadata.comments.push_back(text); }
  void end_meta(int line);
  void data_comment(const std::string& text) { tdm_.segments.back().data_comments.push_back(text); }
  void observation(const std::string& key, const std::string& epoch, const std::string& value, int line);
  Tdm finish(int line);
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  Tdm tdm_;
  bool have_version_ = false;
  std::map<std::string, int> header_seen_;
  std::map<std::string, int> meta_seen_;  // keyword -> line, of the current metadata section
  std::map<int, std::string> participants_;
  std::string path_text_;
};

}  // namespace satgnc::io::detail
