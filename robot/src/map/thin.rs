//! A list most maps never fill, one pointer wide: a map travels by value
//! in every frame, and past 240 bytes a frame's every move is a longer
//! copy (`protocol`'s size test). Freed bodies and sightings are
//! written only once a failure is known.

use serde::{Deserialize, Serialize};

/// A `Vec<T>` that is a null pointer while empty.
#[derive(Clone, Debug)]
pub struct Thin<T>(Option<Box<Vec<T>>>);

impl<T> Default for Thin<T> {
    fn default() -> Self {
        Thin(None)
    }
}

impl<T> Thin<T> {
    /// The list to change, made if it was empty.
    pub fn vec_mut(&mut self) -> &mut Vec<T> {
        self.0.get_or_insert_with(Box::default)
    }
}

impl<T> std::ops::Deref for Thin<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        self.0.as_deref().map_or(&[], |v| v.as_slice())
    }
}

impl<T> From<Vec<T>> for Thin<T> {
    fn from(v: Vec<T>) -> Self {
        Thin(if v.is_empty() { None } else { Some(Box::new(v)) })
    }
}

/// By content: an emptied list equals one never filled.
impl<T: PartialEq> PartialEq for Thin<T> {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

impl<T: Eq> Eq for Thin<T> {}

/// On the wire a plain sequence, as the `Vec` it stands for.
impl<T: Serialize> Serialize for Thin<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        (**self).serialize(s)
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Thin<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Vec::<T>::deserialize(d).map(Thin::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_thin_list_is_a_pointer_and_travels_as_a_vec() {
        assert_eq!(std::mem::size_of::<Thin<(u16, u32)>>(), std::mem::size_of::<usize>());
        let mut t: Thin<(u16, u32)> = Thin::default();
        assert_eq!(postcard::to_allocvec(&t).unwrap(), postcard::to_allocvec(&Vec::<(u16, u32)>::new()).unwrap());
        t.vec_mut().push((3, 70_000));
        let bytes = postcard::to_allocvec(&t).unwrap();
        assert_eq!(bytes, postcard::to_allocvec(&vec![(3u16, 70_000u32)]).unwrap());
        assert_eq!(postcard::from_bytes::<Thin<(u16, u32)>>(&bytes).unwrap(), t);
        t.vec_mut().clear();
        assert_eq!(t, Thin::default(), "emptied equals never filled");
    }
}
