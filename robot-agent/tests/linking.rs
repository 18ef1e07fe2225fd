//! How the `robot-agent` binary is linked (see `build.rs`): at a fixed
//! address, so that starting one of up to 1,000 agents relocates nothing
//! and leaves its pointers' pages shared with the others.

use std::fs;

/// ELF `e_type` of an executable at a fixed address (a PIE is `ET_DYN`, 3).
const ET_EXEC: u16 = 2;

fn elf_type(bytes: &[u8]) -> Result<u16, String> {
    if bytes.get(..4) != Some(b"\x7fELF".as_slice()) {
        return Err("not an ELF file".into());
    }
    // EI_DATA (byte 5): 1 is little-endian; e_type is bytes 16-17.
    let t = bytes.get(16..18).ok_or("truncated ELF header")?;
    Ok(match bytes[5] {
        1 => u16::from_le_bytes([t[0], t[1]]),
        _ => u16::from_be_bytes([t[0], t[1]]),
    })
}

#[test]
fn the_agent_is_not_position_independent() {
    let bin = env!("CARGO_BIN_EXE_robot-agent");
    let bytes = fs::read(bin).unwrap_or_else(|e| panic!("cannot read {bin}: {e}"));
    assert_eq!(
        elf_type(&bytes),
        Ok(ET_EXEC),
        "{bin} is linked as a PIE again: every agent would relocate its data at start"
    );
}

#[test]
fn a_pie_is_told_apart() {
    // This test binary is built the default way: position independent.
    let me = fs::read(std::env::current_exe().unwrap()).unwrap();
    assert_eq!(elf_type(&me), Ok(3));
    assert!(elf_type(b"#!/bin/sh\n").is_err());
}
