//! `nearfield view --script FILE`: a scripted session, one command per line (one per frame),
//! `#` starts a comment. The commands are the changes of [`Change`] (same words as the panel)
//! plus `wait N` (render N frames), `bake-wait` (until a background bake of the probe volume is
//! in the frame), `screenshot FILE.png`, `report` (print the live GPU object counts to stdout)
//! and `quit`.

use super::session::{Change, Side};
use std::path::PathBuf;

#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    Change(Change),
    Wait(u32),
    BakeWait,
    Screenshot(PathBuf),
    Report,
    Quit,
}

/// Parses a whole script; the first malformed line is an error naming it.
pub fn parse(text: &str) -> Result<Vec<Command>, String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        out.push(parse_line(line).map_err(|e| format!("line {}: {e}", i + 1))?);
    }
    Ok(out)
}

fn number<T: std::str::FromStr>(word: &str, what: &str) -> Result<T, String> {
    word.parse()
        .map_err(|_| format!("{what}: expected a number, got '{word}'"))
}

fn parse_line(line: &str) -> Result<Command, String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let (cmd, args) = (words[0], &words[1..]);
    // Optional side word after method/set/quality.
    let (side, args) = match args.first() {
        Some(&"b") | Some(&"B") => (Side::B, &args[1..]),
        Some(&"a") | Some(&"A") => (Side::A, &args[1..]),
        _ => (Side::A, args),
    };
    let one = || -> Result<&str, String> {
        match args {
            [x] => Ok(x),
            _ => Err(format!("{cmd}: expected one argument")),
        }
    };
    let c = match cmd {
        "method" => Change::Method(side, one()?.to_string()),
        "set" => match args {
            [k, v] => Change::Setting(side, k.to_string(), v.to_string()),
            _ => return Err("set: expected KEY VALUE".into()),
        },
        "quality" => Change::Preset(side, one()?.to_string()),
        "aov" => Change::Aov(one()?.to_string()),
        "size" => {
            let s = one()?;
            let (w, h) = s
                .split_once(['x', 'X'])
                .ok_or_else(|| format!("size {s}: expected WIDTHxHEIGHT"))?;
            Change::Size(number(w, "size")?, number(h, "size")?)
        }
        "scene" => Change::Scene(one()?.to_string()),
        "env" => Change::Env(one()?.to_string()),
        "env-intensity" => Change::EnvIntensity(number(one()?, cmd)?),
        "env-rotation" => Change::EnvRotation(number(one()?, cmd)?),
        "exposure" => Change::Exposure(number(one()?, cmd)?),
        "tonemap" => Change::Tonemap(one()?.to_string()),
        "light" => match args {
            [i, on] => Change::Light(
                number(i, "light")?,
                match *on {
                    "on" => true,
                    "off" => false,
                    _ => return Err("light: expected INDEX on|off".into()),
                },
            ),
            _ => return Err("light: expected INDEX on|off".into()),
        },
        "split" => match one()? {
            "off" => Change::Split(None),
            f => Change::Split(Some(number(f, "split")?)),
        },
        "camera" => Change::LoadCamera(PathBuf::from(one()?)),
        "save-camera" => Change::SaveCamera(PathBuf::from(one()?)),
        "orbit" => Change::Orbit(number(one()?, cmd)?),
        "frame" => Change::FrameScene,
        "far" => Change::Far(one()?.to_string()),
        "record-path" => Change::RecordPath(PathBuf::from(one()?)),
        "stop-path" => Change::StopPath,
        "bake-wait" => return Ok(Command::BakeWait),
        "wait" => return Ok(Command::Wait(number(one()?, cmd)?)),
        "screenshot" => return Ok(Command::Screenshot(PathBuf::from(one()?))),
        "report" => return Ok(Command::Report),
        "quit" => return Ok(Command::Quit),
        _ => return Err(format!("unknown command '{cmd}'")),
    };
    Ok(Command::Change(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_command_parses_and_malformed_lines_are_named() {
        let text = "# a session\nmethod b ssdo:samples=8\nset radius 1\nquality b high\n\
                    aov ao\nsize 640x360\nscene builtin:boxes\nenv sky\nenv-intensity 2\n\
                    env-rotation 90\nexposure -1\ntonemap neutral\nlight 0 off\nsplit 0.3\n\
                    split off\ncamera c.json\nsave-camera d.json\norbit 5\nframe\nwait 3\n\
                    screenshot s.png\nreport\nrecord-path p.json\nstop-path\nquit\n";
        let cmds = parse(text).unwrap();
        assert_eq!(cmds.len(), 24);
        assert_eq!(
            cmds[0],
            Command::Change(Change::Method(Side::B, "ssdo:samples=8".into()))
        );
        assert_eq!(
            cmds[1],
            Command::Change(Change::Setting(Side::A, "radius".into(), "1".into()))
        );
        assert_eq!(cmds[4], Command::Change(Change::Size(640, 360)));
        for bad in [
            "fly away",
            "size big",
            "exposure",
            "light 0 dim",
            "set radius",
            "wait -1",
        ] {
            let e = parse(&format!("aov ao\n{bad}\n")).unwrap_err();
            assert!(e.starts_with("line 2:"), "{bad}: {e}");
        }
    }
}
