// `tetcontact campaign`: a case run once per row of a table of experiments, each prediction
// compared with its measurement. The case's `campaign:` block says how a row becomes a run
// (columns → parameters, columns → library materials) and what is compared (a summary measure
// against a column: a number, or a category such as P/NP); any table with those columns works.
#pragma once

#include <string>
#include <vector>

namespace tc {

struct CampaignOptions {
  std::string case_path;
  std::string table_path;
  /// Which rows run: clauses separated by ';', all of which a row must meet; a clause is a
  /// list of row numbers and ranges ("1-20,35"; the table's data rows count from 1) or a
  /// condition on a column (COL=V, COL!=V, COL<V, COL<=V, COL>V, COL>=V; numbers compared as
  /// numbers, = and != compare text otherwise). Empty: every row.
  std::string rows;
  int jobs = 0;         // runs at once; 0: the machine's cores
  std::string out_dir;  // default results/<case name>-campaign
  bool quiet = false;
  bool check = false;  // --check: read and check the case, the table and every row; run nothing
  std::vector<std::string> overrides;  // --set, applied to every run before the row's own
};

/// Runs DIR/runs/row-<N>_<hash>/ (each a `tetcontact run` of one thread; the folder keyed by the
/// run's complete inputs: a finished run of the same inputs is read back, so a campaign resumes
/// after a kill, and another --set never reuses one) and writes DIR/predictions.csv (a line per
/// row: inputs, predicted, measured, error, status), DIR/statistics.json (per comparison and
/// group: error percentiles, or the confusion table and accuracy) and DIR/campaign.png (through
/// tools/post/plot_campaign.py, when python3 with matplotlib is there). Everything is checked
/// before anything runs. Exit codes: 0 every run finished, 1 a run failed (its line says so),
/// 2 bad input: the case, or the table (the message names the row and the column).
int campaign_command(const CampaignOptions& options);

}  // namespace tc
