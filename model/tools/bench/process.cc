// hrpp_bench: child processes (process.h).
#include "process.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "timing.h"

namespace hrpp::bench {

namespace fs = std::filesystem;
using json = nlohmann::json;

Proc run_process(const std::vector<std::string>& argv) {
  int fd[2];
  if (pipe(fd) != 0) throw std::runtime_error("pipe failed");
  const auto t0 = Clock::now();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    dup2(fd[1], 1);
    close(fd[0]);
    close(fd[1]);
    std::vector<char*> av;
    for (const auto& s : argv) av.push_back(const_cast<char*>(s.c_str()));
    av.push_back(nullptr);
    execv(av[0], av.data());
    std::fprintf(stderr, "hrpp_bench: cannot run %s: %s\n", av[0], std::strerror(errno));
    _exit(127);
  }
  close(fd[1]);
  Proc p;
  char buf[65536];
  for (ssize_t k; (k = read(fd[0], buf, sizeof buf)) > 0;) p.out.append(buf, size_t(k));
  close(fd[0]);
  struct rusage ru {};
  wait4(pid, &p.status, 0, &ru);
  p.seconds = since(t0);
  p.max_rss_mb = ru.ru_maxrss / 1024.0;  // Linux: kilobytes
  p.cpu_seconds = double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                  1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  return p;
}

std::string self_exe() { return fs::read_symlink("/proc/self/exe").string(); }

json run_child(const std::string& what, const std::vector<std::string>& args, double* rss) {
  std::vector<std::string> argv{self_exe(), "--child", what};
  argv.insert(argv.end(), args.begin(), args.end());
  const Proc p = run_process(argv);
  if (!WIFEXITED(p.status) || WEXITSTATUS(p.status) != 0)
    throw std::runtime_error("the " + what + " measurement failed (exit status " +
                             std::to_string(p.status) + ")");
  *rss = p.max_rss_mb;
  return json::parse(p.out);
}

}  // namespace hrpp::bench
