// Studies and signals: what a study keeps and says when SIGINT or SIGTERM stops it (study/pool.cpp,
// study/study.hpp's holding_interrupts, interrupt.hpp). A study stopped while its points run, through
// the command line: tests/test_faults.cpp.
#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <string>

#include "bagdem/error.hpp"
#include "bagdem/interrupt.hpp"
#include "bagdem/study/study.hpp"
#include "support.hpp"

using namespace bagdem;
namespace fs = std::filesystem;

// A point whose run ends as the signal comes is kept: its point.done is written, the points not
// started are not, and the study says how many it kept. The runs are a stand-in for `bagdem run`
// that writes a table into its --out, signals the study and exits 0: the pool reaps it before it
// stops, or lets it end in the moment it gives the running points before it kills them.
TEST(Study, APointThatEndsAsTheSignalComesIsKept) {
  const bagdem::testing::TempDir t;
  t.write("fake-run", "#!/bin/sh\nwhile [ $# -gt 0 ]; do if [ \"$1\" = --out ]; then out=$2; fi; shift; done\n"
                      "echo 'a,b' > \"$out/sweep.csv\"\nkill -TERM $PPID\nexit 0\n");
  fs::permissions(t.path / "fake-run", fs::perms::owner_all);
  study::StudySpec spec;
  spec.case_dir = "/nowhere", spec.out_dir = (t.path / "out").string(), spec.source = "test", spec.command = "run --seeds";
  spec.seeds = 3;
  const study::Plan plan = study::make_plan(spec);
  ASSERT_EQ(plan.points.size(), 3u);
  study::PoolOptions opt;
  opt.executable = (t.path / "fake-run").string();
  opt.jobs = 1;
  opt.total = plan.points.size();
  std::string said;
  ::testing::internal::CaptureStderr();
  try {
    study::run_points(plan, {0, 1, 2}, opt);
  } catch (const bagdem::Interrupted& e) {
    said = e.what();
  }
  ::testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("run --seeds (" + spec.out_dir + ") stopped by SIGTERM: 1 of 3 points done and kept"), std::string::npos) << said;
  EXPECT_TRUE(fs::exists(t.path / "out" / "point-000" / "point.done"));
  EXPECT_NE(bagdem::testing::slurp(t.path / "out" / "point-000" / "point.done").find("sweep.csv"), std::string::npos)
      << "point.done records the run's table";
  EXPECT_FALSE(fs::exists(t.path / "out" / "point-001")) << "no point is started after the signal";
}

// A signal the process was started ignoring (a script's `cmd &` ignores SIGINT) stays ignored under
// the guard, and after the other signal, and afterwards.
TEST(Study, ASignalTheProcessIgnoresStaysIgnoredUnderTheGuard) {
  struct sigaction ignore {}, before {}, now {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGINT, &ignore, &before);
  {
    const InterruptGuard guard;
    sigaction(SIGINT, nullptr, &now);
    EXPECT_EQ(now.sa_handler, SIG_IGN);
    raise(SIGINT);  // ignored: nothing recorded, and the process goes on
    EXPECT_EQ(pending_interrupt(), 0);
    raise(SIGTERM);  // caught, recorded; SIGINT is given back its SIG_IGN, not the default action
    EXPECT_EQ(pending_interrupt(), SIGTERM);
    sigaction(SIGINT, nullptr, &now);
    EXPECT_EQ(now.sa_handler, SIG_IGN);
    raise(SIGINT);  // still ignored: this test goes on
  }
  sigaction(SIGINT, nullptr, &now);
  EXPECT_EQ(now.sa_handler, SIG_IGN);
  sigaction(SIGINT, &before, nullptr);
}

// A signal while a study plans or writes its merged tables waits until they are whole (it killed
// the process by the default action, leaving a map.csv without its damper.toml): then the study
// says so and exits 128 + the signal. The pool's own guard inside keeps the signal recorded.
TEST(Study, ASignalWhileAStudyWritesItsTablesWaitsForThemAndIsSaid) {
  ::testing::internal::CaptureStderr();
  bool finished = false;
  const int code = study::holding_interrupts("bagdem sweep", [&] {
    raise(SIGTERM);
    {
      const InterruptGuard pool;  // as run_points holds one
      EXPECT_EQ(pending_interrupt(), SIGTERM);
    }
    finished = true;  // the tables written whole
    return 0;
  });
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(finished);
  EXPECT_EQ(code, 143);
  EXPECT_NE(err.find("bagdem sweep stopped by SIGTERM, which came while it planned or wrote its tables: it finished writing them first"),
            std::string::npos) << err;
  EXPECT_EQ(study::holding_interrupts("bagdem sweep", [] { return 3; }), 3) << "no signal: the study's own code";
}
