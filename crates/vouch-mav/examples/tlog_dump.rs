//! Prints the frames of a recording whose message name matches a filter, with their fields:
//! `cargo run -p vouch-mav --example tlog_dump -- FILE.tlog [NAME-SUBSTRING…]`.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        return Err("usage: tlog_dump FILE.tlog [NAME…]".into());
    };
    let data = std::fs::read(path)?;
    let dialect = vouch_mav::Dialect::default_dialect()?;
    let skip = ["_COUNT_NOT", "XX"];
    for rec in vouch_mav::codec::TlogReader::new(&data, &dialect) {
        let Some(view) = vouch_mav::codec::MessageView::of_frame(&rec.frame, &dialect) else {
            continue;
        };
        let name = view.name();
        if args.len() > 1 && !args[1..].iter().any(|a| name.contains(a.as_str()))
            || skip.contains(&name)
        {
            continue;
        }
        let fields: Vec<String> = view
            .render_fields()
            .into_iter()
            .filter(|(n, _)| {
                !["x", "y", "z", "param2", "param3", "param4", "autocontinue"].contains(&n.as_str())
            })
            .map(|(n, v)| format!("{n}={v}"))
            .collect();
        println!(
            "{} {}/{} {name} {}",
            rec.time_us,
            rec.frame.sysid,
            rec.frame.compid,
            fields.join(" ")
        );
    }
    Ok(())
}
