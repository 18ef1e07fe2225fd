//! zenoh's own protection of a run, as settings of its configuration:
//! mutual TLS (every link encrypted; the world and every robot show a
//! certificate of the run's authority, or the handshake fails) and, in the
//! world's router, access control by certificate name: robot `K` may put
//! only on `out/K`, declare its token only as `alive/K`, subscribe only to
//! `in/K` and to the world's token, and is sent nothing else. Everything
//! else is denied, so a robot's key speaks for that robot alone. Nothing
//! here is a scheme of the project's: it only fills in zenoh's
//! `transport/link/tls` and `access_control` settings.

use serde_json::json;

use crate::credentials::{robot_name, Credentials, Holder};

/// The settings `(key, JSON value)` of mutual TLS for `holder`.
pub fn tls(creds: &Credentials, holder: Holder) -> Result<Vec<(&'static str, String)>, String> {
    creds.check(holder)?;
    let (cert, key) = creds.of(holder);
    let path = |p: std::path::PathBuf| json!(p.to_string_lossy()).to_string();
    let (cert_key, key_key) = match holder {
        Holder::World => ("transport/link/tls/listen_certificate", "transport/link/tls/listen_private_key"),
        Holder::Robot(_) => ("transport/link/tls/connect_certificate", "transport/link/tls/connect_private_key"),
    };
    Ok(vec![
        ("transport/link/tls/root_ca_certificate", path(creds.ca())),
        (cert_key, path(cert)),
        (key_key, path(key)),
        ("transport/link/tls/enable_mtls", "true".into()),
        // The world's certificate must name the host a robot dialled: a
        // certificate for another name (the public roots zenoh also
        // trusts issue such) does not pass for the world's.
        ("transport/link/tls/verify_name_on_connect", "true".into()),
    ])
}

/// The world's `access_control` for `robots` robots under `root`
/// (`gridswarm/<key>`): for each robot, one zenoh rule per message kind
/// and key expression it may use (a zenoh rule allows each of its kinds
/// on each of its key expressions, so one rule of several would allow too
/// much), and one policy tying them to the subject of its certificate's
/// common name.
pub fn access(root: &str, robots: usize) -> String {
    let mut rules = Vec::new();
    let mut subjects = Vec::with_capacity(robots);
    let mut policies = Vec::with_capacity(robots);
    for k in 0..robots {
        let name = robot_name(k);
        let allowed = [
            ("ingress", "put", format!("{root}/out/{k}")),
            ("ingress", "liveliness_token", format!("{root}/alive/{k}")),
            ("ingress", "declare_subscriber", format!("{root}/in/{k}")),
            ("ingress", "declare_liveliness_subscriber", format!("{root}/world")),
            ("ingress", "liveliness_query", format!("{root}/world")),
            ("egress", "put", format!("{root}/in/{k}")),
            ("egress", "liveliness_token", format!("{root}/world")),
            // The world's subscriber, so that the robot's answers go out.
            ("egress", "declare_subscriber", format!("{root}/out/*")),
        ];
        let ids: Vec<String> = (0..allowed.len()).map(|i| format!("{name}.{i}")).collect();
        for ((flow, msg, ke), id) in allowed.iter().zip(&ids) {
            rules.push(json!({
                "id": id,
                "messages": [msg],
                "key_exprs": [ke],
                "flows": [flow],
                "permission": "allow",
            }));
        }
        subjects.push(json!({ "id": name, "cert_common_names": [name] }));
        policies.push(json!({ "rules": ids, "subjects": [name] }));
    }
    json!({
        "enabled": true,
        "default_permission": "deny",
        "rules": rules,
        "subjects": subjects,
        "policies": policies,
    })
    .to_string()
}
