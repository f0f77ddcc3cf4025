//! Checkpoints through the real binary: a render killed with SIGKILL at
//! moments spread over its whole run, or in the middle of a save, and
//! resumed, writes the bytes of the render made at once; SIGINT and
//! SIGTERM write the image so far and the checkpoint; a full disk leaves
//! the last checkpoint whole; a damaged, foreign or other-version
//! checkpoint is refused with status 2 and every file left as it was.
#![cfg(target_os = "linux")]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The render every test makes: about a second on two threads, in 4
/// passes of many tiles.
const SCENE: [&str; 9] = [
    "showcase", "--width", "160", "--height", "120", "--spp", "16", "--passes", "4",
];

fn command(dir: &Path, extra: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_penumbra"));
    cmd.current_dir(dir)
        .arg("render")
        .args(SCENE)
        .args(["--threads", "2", "--quiet"])
        .args(extra)
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    cmd
}

fn run(dir: &Path, extra: &[&str]) -> Output {
    command(dir, extra).output().expect("penumbra runs")
}

fn spawn(dir: &Path, extra: &[&str]) -> Child {
    command(dir, extra).spawn().expect("penumbra starts")
}

/// The image of the render made at once.
fn reference(dir: &Path) -> Vec<u8> {
    let out = run(dir, &["-o", "reference.png"]);
    assert!(out.status.success(), "{}", stderr(&out));
    std::fs::read(dir.join("reference.png")).unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The arguments of a leg that saves to `ckpt` and resumes it if it is
/// there.
fn leg_args(dir: &Path) -> Vec<&'static str> {
    let mut args = vec![
        "-o",
        "out.png",
        "--checkpoint",
        "r.ckpt",
        "--checkpoint-interval",
        "0.01",
    ];
    if dir.join("r.ckpt").exists() {
        args.extend(["--resume", "r.ckpt"]);
    }
    args
}

/// Runs legs to the end, none interrupted.
fn finish(dir: &Path) -> Vec<u8> {
    let out = run(dir, &leg_args(dir));
    assert!(out.status.success(), "{}", stderr(&out));
    std::fs::read(dir.join("out.png")).unwrap()
}

fn kill(child: &mut Child, signal: i32) -> std::process::ExitStatus {
    let pid = child.id() as i32;
    // SAFETY: kill sends a signal to our own child; no memory is touched.
    unsafe {
        libc::kill(pid, signal);
    }
    child.wait().unwrap()
}

/// A checkpoint from a leg interrupted by SIGINT after a moment; its path.
fn first_checkpoint(dir: &Path) -> PathBuf {
    let mut child = spawn(dir, &leg_args(dir));
    std::thread::sleep(Duration::from_millis(300));
    kill(&mut child, libc::SIGINT);
    let ckpt = dir.join("r.ckpt");
    assert!(ckpt.is_file(), "an interrupted leg saves its checkpoint");
    ckpt
}

/// Twenty SIGKILLs, each after a different delay, the render resumed after
/// each: the kills land before the first checkpoint, between tiles, in
/// saves, in the last pass and while the image is written.
#[test]
fn sigkill_at_any_moment_then_resume_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let want = reference(dir.path());
    let started = Instant::now();
    let mut killed = 0;
    let mut finished_early = 0;
    for i in 0..20u64 {
        let delay = Duration::from_millis(15 + (i * 37) % 160);
        let mut child = spawn(dir.path(), &leg_args(dir.path()));
        std::thread::sleep(delay);
        if child.try_wait().unwrap().is_some() {
            finished_early += 1;
            break;
        }
        let status = kill(&mut child, libc::SIGKILL);
        assert!(!status.success());
        killed += 1;
    }
    assert!(killed >= 20 || finished_early > 0, "{killed} kills");
    let got = finish(dir.path());
    assert!(got == want, "the resumed render's bytes differ");
    eprintln!(
        "{killed} kills over {:.1} s",
        started.elapsed().as_secs_f64()
    );
}

/// A crash in the middle of writing a checkpoint (the fault hook aborts
/// after some bytes of the temporary file) leaves the previous one whole:
/// it is byte for byte what it was, and resuming it gives the same image.
#[test]
fn a_crash_inside_a_save_keeps_the_previous_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let want = reference(dir.path());
    let ckpt = first_checkpoint(dir.path());
    for at in [0usize, 1, 17, 1000, 100_000] {
        let before = std::fs::read(&ckpt).expect("a checkpoint to keep");
        let out = command(dir.path(), &leg_args(dir.path()))
            .env("PENUMBRA_FAULT_ABORT_SAVE_AT", at.to_string())
            .output()
            .unwrap();
        assert!(!out.status.success(), "the hook aborts the process");
        assert_eq!(std::fs::read(&ckpt).unwrap(), before, "abort at byte {at}");
    }
    assert!(finish(dir.path()) == want);
}

/// A full disk (a file size limit) while saving: the save fails, the last
/// checkpoint is untouched, and it still resumes to the same bytes.
#[test]
fn a_full_disk_keeps_the_previous_checkpoint() {
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    let want = reference(dir.path());
    let ckpt = first_checkpoint(dir.path());
    let before = std::fs::read(&ckpt).unwrap();
    let mut cmd = command(dir.path(), &leg_args(dir.path()));
    // SAFETY: setrlimit and signal are async-signal-safe and touch only
    // the child.
    unsafe {
        cmd.pre_exec(|| {
            let cap = libc::rlimit {
                rlim_cur: 4096,
                rlim_max: 4096,
            };
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            if libc::setrlimit(libc::RLIMIT_FSIZE, &cap) == 0 {
                Ok(())
            } else {
                Err(std::io::Error::last_os_error())
            }
        });
    }
    let out = cmd.output().unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("cannot save the checkpoint"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read(&ckpt).unwrap(), before);
    let temporaries = std::fs::read_dir(dir.path())
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            name.to_string_lossy().starts_with(".penumbra-checkpoint-")
        })
        .count();
    assert_eq!(temporaries, 0, "no temporary file is left");
    assert!(finish(dir.path()) == want);
}

/// SIGINT and SIGTERM end the render with its image so far, its
/// checkpoint, and 128 + the signal's number.
#[test]
fn sigint_and_sigterm_write_the_image_and_the_checkpoint() {
    for (signal, code) in [(libc::SIGINT, 130), (libc::SIGTERM, 143)] {
        let dir = tempfile::tempdir().unwrap();
        let want = reference(dir.path());
        let child = spawn(dir.path(), &leg_args(dir.path()));
        std::thread::sleep(Duration::from_millis(250));
        let pid = child.id() as i32;
        // SAFETY: as in `kill`.
        unsafe {
            libc::kill(pid, signal);
        }
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(code), "{}", stderr(&out));
        assert!(stderr(&out).contains("--resume"), "{}", stderr(&out));
        let partial = std::fs::read(dir.path().join("out.png")).unwrap();
        assert!(partial != want, "an image of the samples so far");
        assert!(dir.path().join("r.ckpt").is_file());
        assert!(finish(dir.path()) == want);
    }
}

/// Damaged, foreign and other-version checkpoints: status 2, a message
/// naming the file, and the checkpoint and the existing image untouched.
#[test]
fn a_bad_checkpoint_is_refused_and_nothing_is_touched() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(first_checkpoint(dir.path())).unwrap();
    let image = std::fs::read(dir.path().join("out.png")).unwrap();
    let mut flipped = good.clone();
    let middle = flipped.len() / 2;
    flipped[middle] ^= 0x10;
    let mut version = good.clone();
    version[16] ^= 1;
    let cases: [(&str, Vec<u8>, &[&str], &str); 5] = [
        ("truncated", good[..good.len() / 3].to_vec(), &[], "damaged"),
        ("bit flipped", flipped, &[], "damaged"),
        ("another version", version, &[], "cannot resume it"),
        (
            "another scene",
            good.clone(),
            &["--seed", "9"],
            "another render",
        ),
        (
            "not one",
            b"hello".to_vec(),
            &[],
            "not a Penumbra checkpoint",
        ),
    ];
    for (what, bytes, extra, says) in cases {
        let path = dir.path().join("bad.ckpt");
        std::fs::write(&path, &bytes).unwrap();
        let mut args: Vec<&str> = vec![
            "-o",
            "out.png",
            "--checkpoint",
            "bad.ckpt",
            "--resume",
            "bad.ckpt",
        ];
        args.extend(extra);
        let out = run(dir.path(), &args);
        assert_eq!(out.status.code(), Some(2), "{what}: {}", stderr(&out));
        assert!(
            stderr(&out).contains("bad.ckpt"),
            "{what}: {}",
            stderr(&out)
        );
        assert!(stderr(&out).contains(says), "{what}: {}", stderr(&out));
        assert_eq!(std::fs::read(&path).unwrap(), bytes, "{what}");
        assert_eq!(
            std::fs::read(dir.path().join("out.png")).unwrap(),
            image,
            "{what}"
        );
    }
    let missing: PathBuf = dir.path().join("missing.ckpt");
    let out = run(dir.path(), &["--resume", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}
