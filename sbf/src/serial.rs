//! serde for the named values other crates record (behind the `serde` feature): a basis
//! as its registry name (`"sh2"`), an engine format as its id (`"godot-l1"`), an engine
//! frame as `"gltf"` or `"unity"` (both with `sh`), and — with `profile` — a lighting profile as the TOML
//! text [`crate::profile::Profile::to_toml`] writes (read back through its validation).
//! Unknown names are errors that list the known ones.

#[cfg(feature = "sh")]
use crate::recon::engine::{EngineFormat, EngineFrame};
use crate::registry::BasisId;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

impl Serialize for BasisId {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for BasisId {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        BasisId::from_name(&name).ok_or_else(|| {
            let known: Vec<&str> = BasisId::ALL.iter().map(|b| b.name()).collect();
            D::Error::custom(format!("unknown basis '{name}' (one of {})", known.join(", ")))
        })
    }
}

#[cfg(feature = "sh")]
impl Serialize for EngineFormat {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.id())
    }
}

#[cfg(feature = "sh")]
impl<'de> Deserialize<'de> for EngineFormat {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let id = String::deserialize(d)?;
        EngineFormat::ALL.into_iter().find(|f| f.id() == id).ok_or_else(|| {
            let known: Vec<&str> = EngineFormat::ALL.iter().map(|f| f.id()).collect();
            D::Error::custom(format!("unknown engine format '{id}' (one of {})", known.join(", ")))
        })
    }
}

#[cfg(feature = "sh")]
/// An engine frame's recorded name.
fn frame_name(f: EngineFrame) -> &'static str {
    match f {
        EngineFrame::Gltf => "gltf",
        EngineFrame::UnityLeftHanded => "unity",
    }
}

#[cfg(feature = "sh")]
impl Serialize for EngineFrame {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(frame_name(*self))
    }
}

#[cfg(feature = "sh")]
impl<'de> Deserialize<'de> for EngineFrame {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        [EngineFrame::Gltf, EngineFrame::UnityLeftHanded]
            .into_iter()
            .find(|f| frame_name(*f) == name)
            .ok_or_else(|| D::Error::custom(format!("unknown engine frame '{name}' (gltf or unity)")))
    }
}

#[cfg(feature = "profile")]
impl Serialize for crate::profile::Profile {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_toml())
    }
}

#[cfg(feature = "profile")]
impl<'de> Deserialize<'de> for crate::profile::Profile {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        crate::profile::Profile::parse(&text).map_err(|e| D::Error::custom(e.to_string()))
    }
}
