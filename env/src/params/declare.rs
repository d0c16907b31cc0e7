//! [`declare_params!`]: a struct whose parameters are declared once.

/// Declares a struct of parameters, each written once: its doc comment (the help line), its
/// key, its allowed values, its type and its default. The macro writes the struct, its
/// `Default` (the declared defaults) and its [`ParamSet`](crate::params::ParamSet) (listing,
/// parsing, validation).
///
/// Three kinds of field, in any order:
///
/// - a parameter: `#[param("key", DOMAIN)] pub field: TYPE = DEFAULT,`, where the domain is
///   what [`ParamType::Domain`](crate::params::ParamType::Domain) of the type takes
///   ([`Reals`](crate::params::Reals) for `f64`, `lo..=hi` for `usize`) and may be left out
///   for a type whose every value is allowed (`bool`, a named choice);
/// - embedded parameters: `#[params] pub field: TYPE,` (or `= DEFAULT`), a struct declared
///   the same way, whose parameters are listed and set as this struct's own;
/// - state: `field: TYPE = DEFAULT,`, not a parameter.
///
/// After the struct, `check(FN);` names a function `fn(&Self) -> Result<(), Rejection>` that checks
/// the parameters together (embedded structs check themselves first).
///
/// ```
/// use magbench_env::declare_params;
/// use magbench_env::params::{ParamSet, Reals};
///
/// declare_params! {
///     /// A planner's settings.
///     #[derive(Debug, Clone)]
///     pub struct Settings {
///         /// Tries per iteration.
///         #[param("k", 1..=100)]
///         pub tries: usize = 5,
///         /// Probability of sampling the goal region.
///         #[param("goal_bias", Reals::closed(0.0, 1.0))]
///         pub goal_bias: f64 = 0.1,
///         /// Iterations run so far (state, not a parameter).
///         pub iterations: u64 = 0,
///     }
/// }
///
/// let mut s = Settings::default();
/// assert_eq!(s.tries, 5);
/// s.set_param("k", "7").unwrap();
/// assert_eq!(s.tries, 7);
/// assert!(s.set_param("goal_bias", "2").is_err());
/// assert_eq!(s.params().len(), 2);
/// ```
#[macro_export]
macro_rules! declare_params {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident { $($body:tt)* }
        $(check($check:expr);)?
    ) => {
        $crate::declare_params!(@field
            [$(#[$meta])* $vis struct $name] [$($check)?] [] [] []
            $($body)*
        );
    };

    // a parameter
    (@field $head:tt $check:tt [$($fields:tt)*] [$($defaults:tt)*] [$($entries:tt)*]
        $(#[doc = $doc:literal])*
        #[param($key:literal $(, $domain:expr)? $(,)?)]
        $fvis:vis $field:ident : $ty:ty = $default:expr
        $(, $($rest:tt)*)?
    ) => {
        $crate::declare_params!(@field $head $check
            [$($fields)* $(#[doc = $doc])* $fvis $field: $ty,]
            [$($defaults)* $field: $default,]
            [$($entries)* {param $key, $field, $ty, [$($domain)?], [$($doc)*]}]
            $($($rest)*)?
        );
    };

    // embedded parameters
    (@field $head:tt $check:tt [$($fields:tt)*] [$($defaults:tt)*] [$($entries:tt)*]
        $(#[doc = $doc:literal])*
        #[params]
        $fvis:vis $field:ident : $ty:ty $(= $default:expr)?
        $(, $($rest:tt)*)?
    ) => {
        $crate::declare_params!(@field $head $check
            [$($fields)* $(#[doc = $doc])* $fvis $field: $ty,]
            [$($defaults)* $field: $crate::__declared!(@or_default $($default)?),]
            [$($entries)* {params $field}]
            $($($rest)*)?
        );
    };

    // state
    (@field $head:tt $check:tt [$($fields:tt)*] [$($defaults:tt)*] [$($entries:tt)*]
        $(#[doc = $doc:literal])*
        $fvis:vis $field:ident : $ty:ty = $default:expr
        $(, $($rest:tt)*)?
    ) => {
        $crate::declare_params!(@field $head $check
            [$($fields)* $(#[doc = $doc])* $fvis $field: $ty,]
            [$($defaults)* $field: $default,]
            [$($entries)*]
            $($($rest)*)?
        );
    };

    // every field read: the struct, its defaults, its parameter set
    (@field [$(#[$meta:meta])* $vis:vis struct $name:ident] [$($check:expr)?]
        [$($fields:tt)*] [$($defaults:tt)*] [$($entry:tt)*]
    ) => {
        $(#[$meta])*
        $vis struct $name { $($fields)* }

        impl ::core::default::Default for $name {
            fn default() -> Self {
                $name { $($defaults)* }
            }
        }

        impl $crate::params::ParamSet for $name {
            #[allow(unused_mut, clippy::vec_init_then_push)]
            fn params(&self) -> ::std::vec::Vec<$crate::params::ParamInfo> {
                let mut out = ::std::vec::Vec::new();
                $($crate::__declared!(@list self out $entry);)*
                out
            }

            fn set_param(
                &mut self,
                key: &str,
                value: &str,
            ) -> ::core::result::Result<(), $crate::params::ParamError> {
                $($crate::__declared!(@set self key value $entry);)*
                Err($crate::params::ParamError::Unknown(key.to_string()))
            }

            fn check_params(&self) -> ::core::result::Result<(), $crate::input::Rejection> {
                $($crate::__declared!(@check self $entry);)*
                $(($check)(self)?;)?
                Ok(())
            }
        }
    };
}

/// The pieces [`declare_params!`] writes for each field.
#[doc(hidden)]
#[macro_export]
macro_rules! __declared {
    (@or_default) => { ::core::default::Default::default() };
    (@or_default $e:expr) => { $e };

    (@list $s:tt $out:ident {param $key:literal, $field:ident, $ty:ty, [$($domain:expr)?], [$($doc:literal)*]}) => {
        $out.push($crate::params::ParamInfo {
            name: ::std::borrow::Cow::Borrowed($key),
            help: ::std::borrow::Cow::Borrowed(concat!($($doc),*).trim_ascii()),
            range: <$ty as $crate::params::ParamType>::describe(
                &$crate::__declared!(@or_default $($domain)?),
            ),
            value: $crate::params::ParamType::value(&$s.$field),
        });
    };
    (@list $s:tt $out:ident {params $field:ident}) => {
        $out.extend($crate::params::ParamSet::params(&$s.$field));
    };

    (@set $s:tt $key:ident $value:ident {param $k:literal, $field:ident, $ty:ty, [$($domain:expr)?], $docs:tt}) => {
        if $key == $k {
            $s.$field = <$ty as $crate::params::ParamType>::parse(
                $value,
                &$crate::__declared!(@or_default $($domain)?),
            )
            .map_err($crate::params::ParamError::BadValue)?;
            return Ok(());
        }
    };
    (@set $s:tt $key:ident $value:ident {params $field:ident}) => {
        match $crate::params::ParamSet::set_param(&mut $s.$field, $key, $value) {
            Err($crate::params::ParamError::Unknown(_)) => {}
            r => return r,
        }
    };

    (@check $s:tt {param $($x:tt)*}) => {};
    (@check $s:tt {params $field:ident}) => {
        $crate::params::ParamSet::check_params(&$s.$field)?;
    };
}
