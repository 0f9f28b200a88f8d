// Where a render of code under test runs. The grader itself is trusted; the
// pathtracer it grades is not: a submission may try to read the reference
// images or the case list, write outside its case, leave a process behind
// or open a connection. With a sandbox, each render runs
//   - in a staging folder of its own (sandbox_root/pt-render-XXXXXX) that
//     holds copies of what the case needs: the binary, the scene and the
//     files its options name (in/, read-only) and an empty out/;
//   - as an unprivileged account (when the grader runs as root), one per
//     job, so that two renders at a time never share one;
//   - under bubblewrap (mode Bwrap): new user, mount, PID, IPC, UTS and
//     network namespaces, a fresh /tmp, /usr read-only, and nothing else of
//     the machine's files; or, where namespaces are not allowed (mode
//     User), only as that account, with file permissions hiding the rest
//     (check_sandbox() refuses to grade when they do not).
// Afterwards every process of the account is killed and only the regular
// files the grader reads (render.png, render.pfm, render_rate.png,
// stats.json) are copied into the case folder; a link or anything else in
// their place is left behind and the render fails for it.
#pragma once
#include <sys/types.h>

#include <string>
#include <vector>

namespace grader {

enum class SandboxMode { None, Bwrap, User };

// "none", "bwrap", "user".
const char* sandbox_mode_name(SandboxMode mode);
// False when `s` names no mode.
bool parse_sandbox_mode(const std::string& s, SandboxMode* mode);

struct Account {
  std::string name;
  uid_t uid = 0;
  gid_t gid = 0;
};

struct Sandbox {
  SandboxMode mode = SandboxMode::None;
  std::vector<Account> accounts;  // one per job at a time; empty: the grader's own user
  std::string root = "/tmp";      // where staging folders are made

  bool on() const { return mode != SandboxMode::None; }
  // The account of the calling thread's job slot (set_job_slot), or null.
  const Account* account() const;
};

// Looks up each name (comma-separated lists allowed). Throws
// std::runtime_error naming an account that does not exist or is root.
std::vector<Account> lookup_accounts(const std::vector<std::string>& names);

// The job slot of the calling thread: parallel workers set theirs, so that
// each job at a time renders as its own account.
void set_job_slot(int slot);
int job_slot();

// Checks that the sandbox works here and hides what it must: bwrap starts
// (mode Bwrap); as root, there is an account per job; in mode User, no
// account can read any of `secrets` (the references, the case lists, the
// grader, the output folder). Throws std::runtime_error saying what is
// wrong and what to do.
void check_sandbox(const Sandbox& sandbox, int jobs, const std::vector<std::string>& secrets);

// After each render the grader kills every process of its account, so two
// graders rendering as the same account at once would kill each other's
// renders ("killed by signal 9"). Locks a file per account in `lock_dir`
// for as long as this process lives, waiting (and saying so on stderr)
// while another grader holds it. Throws when a lock file cannot be opened.
void lock_accounts(const Sandbox& sandbox, const std::string& lock_dir);

// Mode User only: the accounts see every file of the machine that others
// may read, so a copy of the hidden cases' files anywhere (an instructor's
// checkout, a test's folder, an unpacked zip) would hand them the answer
// key. Searches `search_root` as each account (not /proc, /sys, /dev, /run;
// no link followed) for a readable file with the bytes of any file under
// `keys` (256 bytes or more) and throws naming the first one found. The
// public cases and references are not keys: the starter kit ships them.
void check_no_copies(const Sandbox& sandbox, const std::vector<std::string>& keys, const std::string& search_root = "/");

// One render's staging folder: made by stage(), removed by its destructor.
class Staging {
 public:
  Staging() = default;
  ~Staging();
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;

  // Makes the folder with in/ (copies of `inputs`, each under its file
  // name) and out/ (owned by `account` when there is one). False with
  // *error set when it cannot.
  bool stage(const Sandbox& sandbox, const Account* account, const std::vector<std::string>& inputs,
             std::string* error);
  // Where a file of `inputs` is for the sandboxed program, and where out/
  // is.
  std::string input_path(const std::string& input) const;
  std::string out_path() const;
  // The command that runs `argv` (already in the sandbox's paths) in the
  // sandbox.
  std::vector<std::string> command(const std::vector<std::string>& argv) const;
  // The working folder to give the child (out/ as the grader sees it).
  std::string workdir() const { return dir_ + "/out"; }
  // Copies the regular, unlinked files `names` of out/ into `dest`; a
  // name that is there but is not such a file is listed in *refused.
  void collect(const std::vector<std::string>& names, const std::string& dest, uint64_t max_bytes,
               std::vector<std::string>* refused) const;

 private:
  SandboxMode mode_ = SandboxMode::None;
  std::string dir_;  // empty until staged
};

// Kills every process of the account (what a render left running).
void kill_account_processes(const Account& account);

}  // namespace grader
