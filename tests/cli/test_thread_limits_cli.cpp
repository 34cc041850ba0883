// Threads the system refuses to start (issue 21): under a task limit
// (RLIMIT_NPROC) the command runs on the threads it got, the caller's at
// least, instead of calling std::terminate with joinable threads around.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <grp.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <string_view>
#include <vector>

#include "cli/run_cli.h"

using depthcull::test::example;

namespace {

// Runs the CLI with `args` in a child under RLIMIT_NPROC `tasks`; its exit
// status, -signal when a signal ended it, 77 when the limit cannot be
// applied. Root ignores RLIMIT_NPROC, so the child drops to nobody first.
int run_with_task_limit(rlim_t tasks, const std::vector<std::string>& args) {
    // LeakSanitizer stops the world with a thread of its own at exit, which
    // the limit refuses too: no leak check in the child (sanitized builds).
    std::vector<std::string> env;
    std::string asan = "ASAN_OPTIONS=detect_leaks=0";
    for (char** e = environ; *e; ++e) {
        if (std::string_view(*e).substr(0, 13) == "ASAN_OPTIONS=") asan = std::string(*e) + ":detect_leaks=0";
        else env.emplace_back(*e);
    }
    env.push_back(asan);
    std::vector<char*> envp;
    for (std::string& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    std::vector<char*> argv{const_cast<char*>(DEPTHCULL_CLI_PATH)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_t pid = ::fork();
    if (pid < 0) return -1000;
    if (pid == 0) {
        int null = ::open("/dev/null", O_WRONLY);
        if (null >= 0) {
            ::dup2(null, 1);
            ::dup2(null, 2);
        }
        if (::geteuid() == 0 && (::setgroups(0, nullptr) != 0 || ::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(77);
        rlimit limit{tasks, tasks};
        if (::setrlimit(RLIMIT_NPROC, &limit) != 0) ::_exit(77);
        ::execve(DEPTHCULL_CLI_PATH, argv.data(), envp.data());
        ::_exit(127);
    }
    int status = 0;
    if (::waitpid(pid, &status, 0) != pid) return -1000;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

TEST(ThreadLimitsCli, RunsOnTheThreadsItGets) {
    const std::string scene = example("meadow.json");
    struct Case {
        rlim_t tasks;
        const char* threads;
    };
    // -j 0 is every core: on a machine of one or two it may start none.
    for (Case c : {Case{2, "0"}, Case{2, "8"}, Case{16, "64"}, Case{16, "1000"}, Case{1, "4"}}) {
        int status = run_with_task_limit(c.tasks, {"optimize", scene, "--no-cache", "-j", c.threads, "-o", "-"});
        if (status == 77) GTEST_SKIP() << "cannot drop to nobody or set RLIMIT_NPROC here";
        EXPECT_EQ(status, 0) << "RLIMIT_NPROC " << c.tasks << ", -j " << c.threads;
    }
}

} // namespace
