//! The `kansei` command line. Everything but argument handling and exit codes lives in
//! [`kansei::cli`].

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = kansei::cli::Cli::parse();
    match kansei::cli::run(cli, &mut std::io::stdout().lock()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("kansei: {e}");
            std::process::ExitCode::from(e.exit_code())
        }
    }
}
