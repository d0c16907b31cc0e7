//! With the `ompl` feature, compiles the OMPL shim (ompl/shim.cpp) against the system's OMPL
//! 1.5 (Debian `libompl-dev`), with the compiler and linker flags `pkg-config ompl` gives.
//! Without it, does nothing: the default build needs only the Rust toolchain.

fn main() {
    #[cfg(feature = "ompl")]
    ompl::build();
}

#[cfg(feature = "ompl")]
mod ompl {
    use std::path::Path;
    use std::process::Command;

    /// `pkg-config ompl` with `args`, split on whitespace; exits with a message when OMPL
    /// is missing.
    fn pkg_config(args: &[&str]) -> Vec<String> {
        let out = Command::new("pkg-config").args(args).arg("ompl").output();
        match out {
            Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout)
                .split_whitespace()
                .map(String::from)
                .collect(),
            _ => {
                eprintln!(
                    "the `ompl` feature needs OMPL 1.5 and pkg-config: apt-get install libompl-dev pkg-config"
                );
                std::process::exit(1);
            }
        }
    }

    pub fn build() {
        println!("cargo:rerun-if-changed=ompl/shim.cpp");
        let mut build = cc::Build::new();
        build.cpp(true).file("ompl/shim.cpp").warnings(false);
        for flag in pkg_config(&["--cflags"]) {
            match flag.strip_prefix("-I") {
                Some(dir) => {
                    build.include(dir);
                }
                None => {
                    build.flag(&flag);
                }
            }
        }
        build.compile("magbench_ompl_shim");
        // OMPL's .pc lists libraries as -l names and as full paths (and, on Debian, a bogus
        // -L_link_dirs-NOTFOUND, and libraries that Boost no longer ships); link what exists.
        for lib in pkg_config(&["--libs"]) {
            if let Some(name) = lib.strip_prefix("-l") {
                println!("cargo:rustc-link-lib={name}");
            } else if let Some(dir) = lib.strip_prefix("-L") {
                if Path::new(dir).is_dir() {
                    println!("cargo:rustc-link-search=native={dir}");
                }
            } else if !Path::new(&lib).exists() {
                continue;
            } else if let Some(file) = Path::new(&lib).file_name().and_then(|f| f.to_str()) {
                let stem = file.strip_prefix("lib").and_then(|f| f.split(".so").next());
                if let (Some(stem), Some(dir)) = (stem, Path::new(&lib).parent()) {
                    println!("cargo:rustc-link-search=native={}", dir.display());
                    println!("cargo:rustc-link-lib={stem}");
                }
            }
        }
    }
}
