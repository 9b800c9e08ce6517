// A viewer and a headless page on it, opened together: the set-up of most view tests.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "browser.h"
#include "view_process.h"

namespace ohrp::view::testing {

struct ViewerPage {
  Viewer viewer;
  std::unique_ptr<Browser> browser;
};

// Starts ohrp_view with `args` (its output in `out_file`) and opens its URL + `query` in headless
// Chromium. A fatal failure (no URL printed, no page) leaves `page` half made: the caller checks
// HasFatalFailure().
inline void OpenPage(ViewerPage* page, const std::vector<std::string>& args, const std::string& out_file,
                     const std::string& query = "") {
  StartViewer(&page->viewer, args, out_file);
  ASSERT_FALSE(page->viewer.url.empty()) << ReadFile(page->viewer.out_file);
  page->browser = std::make_unique<Browser>(page->viewer.url + query);
  ASSERT_TRUE(page->browser->ok()) << page->browser->error();
}

}  // namespace ohrp::view::testing
