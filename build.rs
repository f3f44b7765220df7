//! Checks that the system OpenBLAS (linked by openblas-src's `system` feature for clarabel's SDP
//! support) is installed before the long build of the dependencies gets to the link step, and stops
//! with the command that installs it otherwise.

use std::path::Path;

/// Folders where distributions and Homebrew put libopenblas, for machines without pkg-config.
const LIB_DIRS: &[&str] = &[
    "/usr/lib",
    "/usr/lib64",
    "/usr/local/lib",
    "/usr/lib/x86_64-linux-gnu",
    "/usr/lib/aarch64-linux-gnu",
    "/usr/lib/x86_64-linux-gnu/openblas-pthread",
    "/usr/lib/aarch64-linux-gnu/openblas-pthread",
    "/usr/lib64/openblas",
    "/opt/homebrew/opt/openblas/lib",
    "/usr/local/opt/openblas/lib",
];

fn found_without_pkg_config() -> bool {
    let dirs = std::env::var("OPENBLAS_LIB_DIR").into_iter().chain(LIB_DIRS.iter().map(|s| s.to_string()));
    for dir in dirs {
        for file in ["libopenblas.so", "libopenblas.a", "libopenblas.dylib"] {
            if Path::new(&dir).join(file).exists() {
                return true;
            }
        }
    }
    false
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=OPENBLAS_LIB_DIR");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    let probe = pkg_config::Config::new().cargo_metadata(false).env_metadata(false).probe("openblas");
    if probe.is_ok() || found_without_pkg_config() {
        return;
    }
    eprintln!(
        "\nerror: the system library OpenBLAS was not found (filterbench links it for the SDP solver).\n\
         Install it, then build again:\n\
         \x20 Debian/Ubuntu: sudo apt-get install libopenblas-dev gfortran pkg-config\n\
         \x20 Fedora:        sudo dnf install openblas-devel gcc-gfortran pkgconf-pkg-config\n\
         \x20 macOS:         brew install openblas pkg-config\n\
         (or set OPENBLAS_LIB_DIR to the folder that holds libopenblas)\n"
    );
    std::process::exit(1);
}
